// MatFileReader's integrity checks (io/mat_file.h): every damage that matio reads without an
// error, written byte by byte here, must be one Status naming the variable or the byte; what
// MATLAB legitimately writes must read back exactly. Version 7.3 files are written by matio, and
// by HDF5 itself where matio cannot write what MATLAB does (chunked, compressed datasets).

#include "io/mat_file.h"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <matio.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <string>
#include <tuple>
#include <vector>

#include "test_support.h"

namespace accelcal {
namespace {

// ---- A version 5 file, byte by byte (MAT-File Format, "Level 5"), little endian --------

constexpr uint32_t kMiInt8 = 1;
constexpr uint32_t kMiUint8 = 2;
constexpr uint32_t kMiInt32 = 5;
constexpr uint32_t kMiUint32 = 6;
constexpr uint32_t kMiDouble = 9;
constexpr uint32_t kMiMatrix = 14;
constexpr uint32_t kMiCompressed = 15;
constexpr uint32_t kDoubleClass = 6;
constexpr uint32_t kComplexFlag = 0x800;

std::string U32(uint32_t value) { return std::string(reinterpret_cast<const char*>(&value), 4); }

std::string Doubles(const std::vector<double>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(double));
}

std::string Header() {
  std::string header = "MATLAB 5.0 MAT-file, written by mat_file_test";
  header.resize(116, ' ');
  header += std::string(8, '\0');  // subsystem data offset
  header += std::string("\x00\x01", 2) + "IM";
  return header;
}

// A subelement: its tag, its data and the padding to 8 bytes.
std::string Element(uint32_t type, const std::string& data) {
  std::string element = U32(type) + U32(static_cast<uint32_t>(data.size())) + data;
  element.resize((element.size() + 7) / 8 * 8, '\0');
  return element;
}

// A top-level miMATRIX element of class double, its tag included.
std::string Matrix(const std::string& name, int rows, int cols, uint32_t data_type,
                   const std::string& real, const std::string* imaginary = nullptr) {
  const uint32_t flags = kDoubleClass | (imaginary != nullptr ? kComplexFlag : 0);
  std::string body = Element(kMiUint32, U32(flags) + U32(0)) +
                     Element(kMiInt32, U32(rows) + U32(cols)) + Element(kMiInt8, name) +
                     Element(data_type, real);
  if (imaginary != nullptr) body += Element(data_type, *imaginary);
  return U32(kMiMatrix) + U32(static_cast<uint32_t>(body.size())) + body;
}

std::string Deflate(const std::string& bytes) {
  uLongf size = compressBound(bytes.size());
  std::string out(size, '\0');
  EXPECT_EQ(compress(reinterpret_cast<Bytef*>(&out[0]), &size,
                     reinterpret_cast<const Bytef*>(bytes.data()), bytes.size()),
            Z_OK);
  out.resize(size);
  return out;
}

// A miCOMPRESSED element holding `stream`.
std::string Compressed(const std::string& stream) {
  return U32(kMiCompressed) + U32(static_cast<uint32_t>(stream.size())) + stream;
}

std::vector<double> Ramp(int count) {
  std::vector<double> values(count);
  for (int i = 0; i < count; ++i) values[i] = 0.5 + i;
  return values;
}

Status Read(const std::string& path, const std::string& variable, MatMatrix* matrix) {
  MatFileReader reader;
  ACCELCAL_RETURN_IF_ERROR(reader.Open(path));
  return reader.ReadMatrix(variable, matrix);
}

Status Open(const std::string& path) {
  MatFileReader reader;
  return reader.Open(path);
}

// puntos.mat may hold thousands of landmarks: all are read, in file order, with their values,
// by one pass (ReadAllMatrices), and a variable larger than asked for is refused by name
// before its data is read.
TEST(MatFileReader, ReadsEveryVariableInOnePassInFileOrder) {
  testing::ScratchDir scratch;
  std::vector<std::pair<std::string, MatMatrix>> written;
  for (int k = 0; k < 600; ++k) {
    written.push_back({"L" + std::to_string(k), MatMatrix{1, 2, {1.5 * k, -0.25 * k}}});
  }
  ASSERT_TRUE(WriteMatFile(scratch.File("many.mat"), written).ok());
  MatFileReader reader;
  ASSERT_TRUE(reader.Open(scratch.File("many.mat")).ok());
  std::vector<std::pair<std::string, MatMatrix>> read;
  const Status status = reader.ReadAllMatrices(2, "a landmark is 1x2", &read);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(read.size(), written.size());
  for (size_t k = 0; k < read.size(); ++k) {
    EXPECT_EQ(read[k].first, written[k].first);
    EXPECT_EQ(read[k].second.values, written[k].second.values);
  }
  written.push_back({"Big", MatMatrix{3, 1, {1, 2, 3}}});
  ASSERT_TRUE(WriteMatFile(scratch.File("big.mat"), written).ok());
  MatFileReader big;
  ASSERT_TRUE(big.Open(scratch.File("big.mat")).ok());
  const Status refused = big.ReadAllMatrices(2, "a landmark is 1x2", &read);
  EXPECT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("variable 'Big' is 3x1; a landmark is 1x2"), std::string::npos)
      << refused.message();
}

TEST(MatFileIntegrity, ReadsADoubleArrayMatlabStoredAsUint8) {
  // MATLAB stores a double array of small integers as miUINT8: legal, counted by values.
  testing::ScratchDir scratch;
  const std::string element = Matrix("datos", 3, 2, kMiUint8, std::string("\1\2\3\4\5\6", 6));
  for (const std::string& file : {Header() + element, Header() + Compressed(Deflate(element))}) {
    MatMatrix matrix;
    ASSERT_TRUE(Read(scratch.Write("ensayo.mat", file), "datos", &matrix).ok());
    EXPECT_EQ(matrix.rows, 3);
    EXPECT_EQ(matrix.cols, 2);
    EXPECT_EQ(matrix.values, (std::vector<double>{1, 2, 3, 4, 5, 6}));
  }
}

TEST(MatFileIntegrity, RefusesDataShorterOrLongerThanItsDimensions) {
  testing::ScratchDir scratch;
  const std::string short_data = Matrix("datos", 5, 2, kMiDouble, Doubles(Ramp(9)));
  MatMatrix matrix;
  EXPECT_ERROR_CONTAINS(Read(scratch.Write("a.mat", Header() + short_data), "datos", &matrix),
                        "variable 'datos' declares 5x2 values but its data holds 9 (72 bytes of "
                        "double); the file is damaged");
  EXPECT_ERROR_CONTAINS(
      Read(scratch.Write("b.mat", Header() + Compressed(Deflate(short_data))), "datos", &matrix),
      "variable 'datos' declares 5x2 values but its data holds 9");
  const std::string long_data = Matrix("datos", 5, 2, kMiUint8, std::string(11, '\1'));
  EXPECT_ERROR_CONTAINS(Read(scratch.Write("c.mat", Header() + long_data), "datos", &matrix),
                        "variable 'datos' declares 5x2 values but its data holds 11 (11 bytes of "
                        "uint8)");
  const std::string imaginary = Doubles(Ramp(8));
  const std::string complex = Matrix("datos", 5, 2, kMiDouble, Doubles(Ramp(10)), &imaginary);
  EXPECT_ERROR_CONTAINS(Read(scratch.Write("d.mat", Header() + complex), "datos", &matrix),
                        "variable 'datos' declares 5x2 values but its imaginary data holds 8");
}

TEST(MatFileIntegrity, RefusesACompressedVariableThatInflatesShort) {
  // A complete zlib stream 8 bytes (one value) short of its miMATRIX tag: matio returns the
  // variable as zeros.
  testing::ScratchDir scratch;
  const std::string tita = Matrix("tita", 100, 1, kMiDouble, Doubles(Ramp(100)));
  const std::string element = Matrix("datos", 100, 2, kMiDouble, Doubles(Ramp(200)));
  const std::string file =
      Header() + tita + Compressed(Deflate(element.substr(0, element.size() - 8)));
  MatMatrix matrix;
  EXPECT_ERROR_CONTAINS(
      Read(scratch.Write("a.mat", file), "datos", &matrix),
      "variable 'datos' (compressed, at byte " + std::to_string(128 + tita.size()) +
          ") inflates to " + std::to_string(element.size() - 16) + " bytes, fewer than the " +
          std::to_string(element.size() - 8) + " its header declares; the file is damaged");
}

TEST(MatFileIntegrity, RefusesACutLongOrPaddedCompressedStream) {
  testing::ScratchDir scratch;
  const std::string element = Matrix("datos", 100, 2, kMiDouble, Doubles(Ramp(200)));
  const std::string stream = Deflate(element);
  MatMatrix matrix;
  EXPECT_ERROR_CONTAINS(
      Read(scratch.Write("cut.mat", Header() + Compressed(stream.substr(0, stream.size() / 2))),
           "datos", &matrix),
      "variable 'datos' (compressed, at byte 128) is cut short: its zlib stream stops after");
  EXPECT_ERROR_CONTAINS(
      Read(scratch.Write("junk.mat", Header() + Compressed(stream + "junk")), "datos", &matrix),
      "variable 'datos' (compressed, at byte 128) has 4 bytes after the end of its zlib stream");
  EXPECT_ERROR_CONTAINS(
      Read(scratch.Write("long.mat",
                         Header() + Compressed(Deflate(element + U32(0) + U32(0) + "more"))),
           "datos", &matrix),
      "variable 'datos' (compressed, at byte 128) inflates to more than the");
  std::string corrupt = stream;
  corrupt[0] = 0x7f;  // not a zlib header
  EXPECT_ERROR_CONTAINS(
      Read(scratch.Write("corrupt.mat", Header() + Compressed(corrupt)), "datos", &matrix),
      "the compressed variable at byte 128 does not inflate (zlib: ");
}

TEST(MatFileIntegrity, RefusesAVariableNameThatAppearsTwice) {
  testing::ScratchDir scratch;
  const std::string first = Matrix("tita", 4, 1, kMiDouble, Doubles(Ramp(4)));
  const std::string datos = Matrix("datos", 4, 2, kMiDouble, Doubles(Ramp(8)));
  const std::string last = Compressed(Deflate(Matrix("tita", 4, 1, kMiDouble, Doubles(Ramp(4)))));
  MatMatrix matrix;
  EXPECT_ERROR_CONTAINS(
      Read(scratch.Write("a.mat", Header() + first + datos + last), "tita", &matrix),
      "variable 'tita' appears 2 times in the file; MATLAB would read the last, "
      "other readers the first: save it again with one of each");
  // Version 4: type 0 (double, little endian), rows, cols, imagf, namlen; name; values.
  const auto v4 = [](const std::string& name, double value) {
    return U32(0) + U32(1) + U32(1) + U32(0) + U32(static_cast<uint32_t>(name.size() + 1)) + name +
           '\0' + Doubles({value});
  };
  EXPECT_ERROR_CONTAINS(
      Read(scratch.Write("v4.mat", v4("t", 1) + v4("Aerr", 2) + v4("t", 3)), "t", &matrix),
      "variable 't' appears 2 times in the file");
}

TEST(MatFileIntegrity, RefusesFoldersDevicesAndPipesWithoutReadingThem) {
  testing::ScratchDir scratch;
  EXPECT_ERROR_CONTAINS(Open(scratch.File("")), "is a folder, not a MAT file");
  EXPECT_ERROR_CONTAINS(Open("/dev/zero"), "is a character device, not a MAT file");
  ASSERT_EQ(mkfifo(scratch.File("fifo.mat").c_str(), 0600), 0);
  EXPECT_ERROR_CONTAINS(Open(scratch.File("fifo.mat")), "is a pipe (FIFO), not a MAT file");
}

TEST(MatFileIntegrity, RefusesALargeSparseFileQuicklyAndWithoutItsMemory) {
  // 2 GiB of zeros that occupy no disk: mapped, not read, and refused by its first bytes.
  testing::ScratchDir scratch;
  const std::string path = scratch.Write("zeros.mat", "");
  ASSERT_EQ(truncate(path.c_str(), 2ll << 30), 0);
  rusage before;
  getrusage(RUSAGE_SELF, &before);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_ERROR_CONTAINS(Open(path), "the version 4 matrix at byte 0 declares 0x0 values");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  rusage after;
  getrusage(RUSAGE_SELF, &after);
  EXPECT_LT(after.ru_maxrss - before.ru_maxrss, 64 * 1024) << "kB";
}

// ---- Version 7.3 (HDF5) ------------------------------------------------------------------

std::string WriteMat73(const testing::ScratchDir& scratch, const std::string& name, int rows) {
  const std::string path = scratch.File(name);
  mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, MAT_FT_MAT73);
  EXPECT_NE(mat, nullptr) << "libmatio was built without HDF5";
  if (mat == nullptr) return path;
  std::vector<double> tita = Ramp(rows);
  std::vector<double> datos = Ramp(2 * rows);
  size_t tita_dims[2] = {static_cast<size_t>(rows), 1};
  size_t datos_dims[2] = {static_cast<size_t>(rows), 2};
  for (auto [variable_name, dims, values] : {std::make_tuple("tita", tita_dims, tita.data()),
                                             std::make_tuple("datos", datos_dims, datos.data())}) {
    matvar_t* var = Mat_VarCreate(variable_name, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, values,
                                  MAT_F_DONT_COPY_DATA);
    EXPECT_EQ(Mat_VarWrite(mat, var, MAT_COMPRESSION_NONE), 0);
    Mat_VarFree(var);
  }
  Mat_Close(mat);
  return path;
}

// Opens `path`, expecting HDF5 to print nothing whatever it finds.
Status OpenSilently(const std::string& path) {
  ::testing::internal::CaptureStderr();
  const Status status = Open(path);
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  return status;
}

// Opens `bytes` with the first four bytes of `signature` in them overwritten.
Status OpenOverwritten(const testing::ScratchDir& scratch, std::string bytes,
                       const std::string& signature) {
  const size_t at = bytes.find(signature);
  EXPECT_NE(at, std::string::npos) << "no " << signature << " in the file";
  if (at == std::string::npos) return Status::Error("no signature");
  bytes.replace(at, 4, "XXXX");
  return OpenSilently(scratch.Write("damaged.mat", bytes));
}

TEST(MatFile73, ReadsWhatMatioWroteSilently) {
  testing::ScratchDir scratch;
  const std::string path = WriteMat73(scratch, "ensayo.mat", 50);
  ::testing::internal::CaptureStderr();
  MatFileReader reader;
  const Status opened = reader.Open(path);
  std::vector<std::string> names;
  MatMatrix datos;
  const Status listed = reader.ListVariables(&names);
  const Status read = reader.ReadMatrix("datos", &datos);
  MatMatrix missing;
  const Status absent = reader.ReadMatrix("theta", &missing);
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  ASSERT_TRUE(opened.ok()) << opened.message();
  ASSERT_TRUE(listed.ok());
  EXPECT_EQ(names, (std::vector<std::string>{"datos", "tita"}));  // HDF5 lists by name
  ASSERT_TRUE(read.ok()) << read.message();
  EXPECT_EQ(datos.rows, 50);
  EXPECT_EQ(datos.cols, 2);
  EXPECT_EQ(datos.values, Ramp(100));
  EXPECT_ERROR_CONTAINS(absent, "variable 'theta' not found (the file has: datos, tita)");
}

TEST(MatFile73, RefusesATruncatedCopyInOneLineOnly) {
  testing::ScratchDir scratch;
  const std::string bytes = testing::ReadText(WriteMat73(scratch, "whole.mat", 50));
  const std::string path = scratch.Write("cut.mat", bytes.substr(0, bytes.size() * 6 / 10));
  ::testing::internal::CaptureStderr();
  const Status status = Open(path);
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  EXPECT_ERROR_CONTAINS(status, "the file is truncated: HDF5 wrote " +
                                    std::to_string(bytes.size()) + " bytes but the file has " +
                                    std::to_string(bytes.size() * 6 / 10) + "; copy it again");
  EXPECT_ERROR_CONTAINS(Open(scratch.Write("header.mat", bytes.substr(0, 300))),
                        "the file is truncated: 300 bytes, less than a version 7.3 MAT file's "
                        "header and HDF5 signature");
}

TEST(MatFile73, RefusesADamagedFileInHdf5sWordsOnOneLine) {
  // The root group's B-tree signature overwritten: HDF5 opens the file but cannot list it.
  testing::ScratchDir scratch;
  const Status status =
      OpenOverwritten(scratch, testing::ReadText(WriteMat73(scratch, "whole.mat", 50)), "TREE");
  EXPECT_ERROR_CONTAINS(status, "the version 7.3 file (");
  EXPECT_ERROR_CONTAINS(status, "); the file is damaged");
}

// ---- Integer classes -----------------------------------------------------------------------

template <typename T>
void WriteIntegers(mat_t* mat, const char* name, matio_classes class_type, matio_types type,
                   std::vector<T> values) {
  size_t dims[2] = {values.size(), 1};
  matvar_t* var = Mat_VarCreate(name, class_type, type, 2, dims, values.data(), 0);
  ASSERT_NE(var, nullptr);
  EXPECT_EQ(Mat_VarWrite(mat, var, MAT_COMPRESSION_NONE), 0);
  Mat_VarFree(var);
}

// ReadMatrix keeps refusing integers (the course's files hold doubles, and an int32 angle is a
// mistake there); ReadNumericMatrix widens them, each value exactly, and refuses a 64-bit value
// no double holds.
TEST(MatFileReader, WidensIntegersExactlyOnlyWhenAsked) {
  testing::ScratchDir scratch;
  constexpr int64_t k2To53 = int64_t{1} << 53;
  for (mat_ft version : {MAT_FT_MAT5, MAT_FT_MAT73}) {
    const std::string path = scratch.File(version == MAT_FT_MAT5 ? "v5.mat" : "v73.mat");
    mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, version);
    ASSERT_NE(mat, nullptr);
    WriteIntegers<int16_t>(mat, "i16", MAT_C_INT16, MAT_T_INT16, {-32768, -1, 0, 32767});
    WriteIntegers<uint32_t>(mat, "u32", MAT_C_UINT32, MAT_T_UINT32, {0, 4294967295u});
    WriteIntegers<int64_t>(mat, "i64", MAT_C_INT64, MAT_T_INT64,
                           {-k2To53, k2To53, k2To53 + 2, int64_t{1} << 62});
    WriteIntegers<int64_t>(mat, "i64_odd", MAT_C_INT64, MAT_T_INT64, {0, k2To53 + 1});
    WriteIntegers<uint64_t>(mat, "u64_max", MAT_C_UINT64, MAT_T_UINT64, {0, UINT64_MAX});
    WriteIntegers<int64_t>(mat, "i64_max", MAT_C_INT64, MAT_T_INT64, {INT64_MAX});
    size_t dims[2] = {2, 1};
    uint8_t flags[2] = {1, 0};
    matvar_t* logical =
        Mat_VarCreate("flags", MAT_C_UINT8, MAT_T_UINT8, 2, dims, flags, MAT_F_LOGICAL);
    EXPECT_EQ(Mat_VarWrite(mat, logical, MAT_COMPRESSION_NONE), 0);
    Mat_VarFree(logical);
    Mat_Close(mat);
    MatFileReader reader;
    ASSERT_TRUE(reader.Open(path).ok()) << path;
    MatMatrix matrix;
    EXPECT_ERROR_CONTAINS(reader.ReadMatrix("i16", &matrix),
                          "variable 'i16' is int16; expected a real double matrix");
    for (const auto& [name, expected] :
         {std::make_pair("i16", std::vector<double>{-32768, -1, 0, 32767}),
          std::make_pair("u32", std::vector<double>{0, 4294967295.0}),
          std::make_pair("i64", std::vector<double>{-9007199254740992.0, 9007199254740992.0,
                                                    9007199254740994.0, 4611686018427387904.0})}) {
      const Status read = reader.ReadNumericMatrix(name, &matrix);
      ASSERT_TRUE(read.ok()) << read.message();
      EXPECT_EQ(matrix.values, expected) << name;
    }
    EXPECT_ERROR_CONTAINS(reader.ReadNumericMatrix("i64_odd", &matrix),
                          "variable 'i64_odd' is int64 and its value 9007199254740993 (element 2) "
                          "is beyond 2^53, where a double cannot hold every integer");
    EXPECT_ERROR_CONTAINS(reader.ReadNumericMatrix("u64_max", &matrix),
                          "variable 'u64_max' is uint64 and its value 18446744073709551615");
    EXPECT_ERROR_CONTAINS(reader.ReadNumericMatrix("i64_max", &matrix),
                          "variable 'i64_max' is int64 and its value 9223372036854775807");
    EXPECT_ERROR_CONTAINS(reader.ReadNumericMatrix("flags", &matrix),
                          "variable 'flags' is logical; expected a real numeric matrix");
    std::vector<MatVariableDescription> described;
    ASSERT_TRUE(reader.DescribeVariables(&described).ok());
    std::string classes;
    for (const MatVariableDescription& variable : described)
      classes += variable.name + ":" + variable.class_name + " ";
    EXPECT_NE(classes.find("flags:logical "), std::string::npos) << classes;
    EXPECT_NE(classes.find("i16:int16 "), std::string::npos) << classes;
    EXPECT_NE(classes.find("u64_max:uint64 "), std::string::npos) << classes;
  }
}

// ---- Version 7.3 written by HDF5, as MATLAB writes it ---------------------------------------
// MATLAB's -v7.3 stores a variable as a chunked, deflated dataset (matio writes contiguous
// ones), in a file with a 512-byte user block holding the MAT header, the class in a
// fixed-length, null-terminated MATLAB_class attribute, the dimensions reversed (column-major).

struct Hdf5Variable {
  std::string name;
  int rows = 0;
  int cols = 0;
  std::vector<double> values;  // column-major, rows * cols
  std::vector<hsize_t> chunk;  // in HDF5's order (cols, rows); empty: contiguous
  bool deflate = false;
  enum Written { kAll, kFirstColumn, kNothing } written = kAll;
  bool fill_value = true;  // false: no fill value defined
};

std::string WriteHdf5Mat(const testing::ScratchDir& scratch, const std::string& name,
                         const std::vector<Hdf5Variable>& variables) {
  const std::string path = scratch.File(name);
  const hid_t creation = H5Pcreate(H5P_FILE_CREATE);
  H5Pset_userblock(creation, 512);
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, creation, H5P_DEFAULT);
  H5Pclose(creation);
  EXPECT_GE(file, 0);
  for (const Hdf5Variable& variable : variables) {
    const hsize_t dims[2] = {static_cast<hsize_t>(variable.cols),
                             static_cast<hsize_t>(variable.rows)};
    const hid_t space = H5Screate_simple(2, dims, nullptr);
    const hid_t properties = H5Pcreate(H5P_DATASET_CREATE);
    if (!variable.chunk.empty()) H5Pset_chunk(properties, 2, variable.chunk.data());
    if (variable.deflate) H5Pset_deflate(properties, 3);
    if (!variable.fill_value) {
      H5Pset_fill_value(properties, H5T_NATIVE_DOUBLE, nullptr);
      H5Pset_fill_time(properties, H5D_FILL_TIME_NEVER);
    }
    const hid_t dataset = H5Dcreate2(file, variable.name.c_str(), H5T_IEEE_F64LE, space,
                                     H5P_DEFAULT, properties, H5P_DEFAULT);
    EXPECT_GE(dataset, 0) << variable.name;
    if (variable.written == Hdf5Variable::kAll) {
      EXPECT_GE(H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                         variable.values.data()),
                0);
    } else if (variable.written == Hdf5Variable::kFirstColumn) {
      const hsize_t start[2] = {0, 0};
      const hsize_t count[2] = {1, dims[1]};
      const hid_t memory = H5Screate_simple(2, count, nullptr);
      H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr);
      EXPECT_GE(
          H5Dwrite(dataset, H5T_NATIVE_DOUBLE, memory, space, H5P_DEFAULT, variable.values.data()),
          0);
      H5Sclose(memory);
    }
    const hid_t text = H5Tcopy(H5T_C_S1);
    H5Tset_size(text, 6);
    H5Tset_strpad(text, H5T_STR_NULLTERM);
    const hid_t scalar = H5Screate(H5S_SCALAR);
    const hid_t attribute =
        H5Acreate2(dataset, "MATLAB_class", text, scalar, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(attribute, text, "double");
    H5Aclose(attribute);
    H5Sclose(scalar);
    H5Tclose(text);
    H5Dclose(dataset);
    H5Pclose(properties);
    H5Sclose(space);
  }
  H5Fclose(file);
  std::string bytes = testing::ReadText(path);
  std::string header =
      "MATLAB 7.3 MAT-file, Platform: GLNXA64, written by mat_file_test HDF5 schema 1.00 .";
  header.resize(116, ' ');
  header += std::string(8, '\0') + std::string("\x00\x02", 2) + "IM";
  bytes.replace(0, header.size(), header);
  return scratch.Write(name, bytes);
}

Hdf5Variable Variable(const std::string& name, int rows, int cols, std::vector<hsize_t> chunk,
                      bool deflate) {
  Hdf5Variable variable;
  variable.name = name;
  variable.rows = rows;
  variable.cols = cols;
  variable.values = Ramp(rows * cols);
  variable.chunk = std::move(chunk);
  variable.deflate = deflate;
  return variable;
}

TEST(MatFile73, ReadsChunkedAndDeflatedVariablesAsMatlabWritesThem) {
  // Deflated chunks (HDF5 says PART_ALLOCATED: the stored bytes are fewer than the values'),
  // and plain chunks whose last ones overhang the dimensions (more bytes than the values').
  testing::ScratchDir scratch;
  const std::string path =
      WriteHdf5Mat(scratch, "chunked.mat",
                   {Variable("acc", 1000, 3, {1, 128}, true),
                    Variable("t", 1000, 1, {1, 300}, false), Variable("w", 7, 5, {2, 2}, true)});
  ::testing::internal::CaptureStderr();
  MatFileReader reader;
  const Status opened = reader.Open(path);
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  ASSERT_TRUE(opened.ok()) << opened.message();
  for (const auto& [name, rows, cols] :
       {std::make_tuple("acc", 1000, 3), std::make_tuple("t", 1000, 1),
        std::make_tuple("w", 7, 5)}) {
    MatMatrix matrix;
    const Status read = reader.ReadMatrix(name, &matrix);
    ASSERT_TRUE(read.ok()) << read.message();
    EXPECT_EQ(matrix.rows, rows) << name;
    EXPECT_EQ(matrix.cols, cols) << name;
    EXPECT_EQ(matrix.values, Ramp(rows * cols)) << name;
  }
}

TEST(MatFile73, ReadsAPartlyWrittenChunkedVariableWithItsFillValue) {
  // MATLAB's matfile writes a slice of a variable; the chunks never written read as the fill
  // value, zero, in HDF5 and MATLAB alike.
  testing::ScratchDir scratch;
  Hdf5Variable partial = Variable("acc", 30, 3, {1, 10}, true);
  partial.written = Hdf5Variable::kFirstColumn;
  MatMatrix matrix;
  const Status read = Read(WriteHdf5Mat(scratch, "slice.mat", {partial}), "acc", &matrix);
  ASSERT_TRUE(read.ok()) << read.message();
  std::vector<double> expected = Ramp(30);
  expected.resize(90, 0.0);
  EXPECT_EQ(matrix.values, expected);
}

TEST(MatFile73, RefusesADatasetWithoutStoredDataOrAChunkIndex) {
  testing::ScratchDir scratch;
  // Never written: HDF5 would return zeros, contiguous or chunked.
  for (bool chunked : {false, true}) {
    Hdf5Variable empty = Variable(
        "acc", 30, 3, chunked ? std::vector<hsize_t>{1, 10} : std::vector<hsize_t>{}, chunked);
    empty.written = Hdf5Variable::kNothing;
    const Status status = OpenSilently(WriteHdf5Mat(scratch, "unwritten.mat", {empty}));
    EXPECT_ERROR_CONTAINS(status,
                          "variable 'acc' has no stored data (HDF5 would return zeros); "
                          "the file is damaged");
  }
  // Chunks missing and no fill value: HDF5 would return whatever its buffer held.
  Hdf5Variable undefined = Variable("acc", 30, 3, {1, 10}, false);
  undefined.written = Hdf5Variable::kFirstColumn;
  undefined.fill_value = false;
  EXPECT_ERROR_CONTAINS(Open(WriteHdf5Mat(scratch, "undefined.mat", {undefined})),
                        "variable 'acc' stores 3 of its 9 chunks and has no fill value for the "
                        "others (HDF5 would return undefined values); the file is damaged");
  // The chunk index's B-tree node (signature TREE, node type 1) damaged.
  const Status damaged =
      OpenOverwritten(scratch,
                      testing::ReadText(WriteHdf5Mat(scratch, "whole.mat",
                                                     {Variable("acc", 30, 3, {1, 10}, true)})),
                      std::string("TREE\x01", 5));
  EXPECT_ERROR_CONTAINS(damaged, "variable 'acc' has data HDF5 cannot locate (");
  EXPECT_ERROR_CONTAINS(damaged, "); the file is damaged");
}

}  // namespace
}  // namespace accelcal
