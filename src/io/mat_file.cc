#include "io/mat_file.h"

#include <matio.h>

#include <algorithm>
#include <cctype>

#include "io/atomic_file.h"
#include "io/mat73_reader.h"
#include "io/mat_integrity.h"
#include "io/matio_support.h"

namespace accelcal {
namespace {

using mat_internal::CheckMatFile;
using mat_internal::CheckReadable;
using mat_internal::CopyValues;
using mat_internal::InfoOf;
using mat_internal::InstallMatioLogger;
using mat_internal::kValuesRead;
using mat_internal::kValuesRefused;
using mat_internal::kZlibExpansion;
using mat_internal::LastMatioMessage;
using mat_internal::Mat73Variable;
using mat_internal::MatClasses;
using mat_internal::MatlabClassName;
using mat_internal::MatVersion;
using mat_internal::ReadMat73InChild;
using mat_internal::VariableInfo;

Status VariableNotFound(const std::string& variable, const std::vector<std::string>& names) {
  std::string listing;
  for (const std::string& name : names) listing += (listing.empty() ? "" : ", ") + name;
  // Names come from the file: nothing unprintable may garble or break the line.
  for (char& c : listing) {
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  }
  return Status::Error("variable '" + variable + "' not found (the file has: " +
                       (listing.empty() ? "no variables" : listing) + ")");
}

}  // namespace

struct MatFileReader::Impl {
  mat_t* mat = nullptr;
  uint64_t file_size = 0;
  bool mat73 = false;
  std::vector<Mat73Variable> mat73_variables;  // what the version 7.3 reader sent
  // The headers of the file's variables, in file order.
  Status Infos(std::vector<VariableInfo>* infos) {
    infos->clear();
    if (mat73) {
      for (const Mat73Variable& variable : mat73_variables) infos->push_back(variable.info);
      return Status::Ok();
    }
    Mat_Rewind(mat);
    LastMatioMessage().clear();
    while (matvar_t* info = Mat_VarReadNextInfo(mat)) {
      if (info->name != nullptr) infos->push_back(InfoOf(info));
      Mat_VarFree(info);
    }
    Mat_Rewind(mat);
    if (!LastMatioMessage().empty()) {
      return Status::Error("cannot list the variables (" + LastMatioMessage() + ")");
    }
    return Status::Ok();
  }
  ~Impl() {
    if (mat != nullptr) Mat_Close(mat);
  }
};

MatFileReader::MatFileReader() : impl_(new Impl) {}
MatFileReader::~MatFileReader() = default;

Status MatFileReader::Open(const std::string& path) {
  InstallMatioLogger();
  MatVersion version = MatVersion::kMat4;
  ACCELCAL_RETURN_IF_ERROR(CheckMatFile(path, &impl_->file_size, &version));
  if (version == MatVersion::kMat73) {
    impl_->mat73 = true;
    return ReadMat73InChild(path, impl_->file_size, &impl_->mat73_variables);
  }
  LastMatioMessage().clear();
  impl_->mat = Mat_Open(path.c_str(), MAT_ACC_RDONLY);
  if (impl_->mat == nullptr) {
    return Status::Error("not a readable MAT file" +
                         (LastMatioMessage().empty() ? "" : " (" + LastMatioMessage() + ")") +
                         "; save it from MATLAB/Octave with save -v7 or -v6");
  }
  return Status::Ok();
}

Status MatFileReader::ListVariables(std::vector<std::string>* names) {
  names->clear();
  std::vector<VariableInfo> infos;
  ACCELCAL_RETURN_IF_ERROR(impl_->Infos(&infos));
  for (const VariableInfo& info : infos) names->push_back(info.name);
  return Status::Ok();
}

Status MatFileReader::DescribeVariables(std::vector<MatVariableDescription>* variables) {
  variables->clear();
  std::vector<VariableInfo> infos;
  ACCELCAL_RETURN_IF_ERROR(impl_->Infos(&infos));
  for (const VariableInfo& info : infos)
    variables->push_back({info.name, MatlabClassName(info), info.dims, info.fields});
  return Status::Ok();
}

Status MatFileReader::ReadMatrix(const std::string& variable, MatMatrix* matrix) {
  return Read(variable, false, matrix);
}

Status MatFileReader::ReadNumericMatrix(const std::string& variable, MatMatrix* matrix) {
  return Read(variable, true, matrix);
}

Status MatFileReader::Read(const std::string& variable, bool integers, MatMatrix* matrix) {
  const std::string where = "variable '" + variable + "'";
  const MatClasses classes = integers ? MatClasses::kNumeric : MatClasses::kFloating;
  if (impl_->mat73) {
    for (const Mat73Variable& candidate : impl_->mat73_variables) {
      if (candidate.info.name != variable) continue;
      ACCELCAL_RETURN_IF_ERROR(
          CheckReadable(candidate.info, impl_->file_size, kZlibExpansion, classes));
      if (candidate.values_kind == kValuesRefused) return Status::Error(candidate.read_error);
      if (candidate.values_kind != kValuesRead) {
        return Status::Error(
            "cannot read " + where +
            (candidate.read_error.empty() ? "" : " (" + candidate.read_error + ")"));
      }
      matrix->rows = static_cast<int>(candidate.info.dims[0]);
      matrix->cols = static_cast<int>(candidate.info.dims[1]);
      matrix->values = candidate.values;
      return Status::Ok();
    }
    // The listing only helps the message; a file that cannot list its variables still
    // lacks this one.
    std::vector<std::string> names;
    if (!ListVariables(&names).ok()) names.clear();
    return VariableNotFound(variable, names);
  }
  Mat_Rewind(impl_->mat);
  LastMatioMessage().clear();
  matvar_t* info = Mat_VarReadInfo(impl_->mat, variable.c_str());
  if (info == nullptr) {
    // The listing only helps the message; a file that cannot list its variables still
    // lacks this one.
    std::vector<std::string> names;
    if (!ListVariables(&names).ok()) names.clear();
    return VariableNotFound(variable, names);
  }
  const std::unique_ptr<matvar_t, void (*)(matvar_t*)> info_owner(info, Mat_VarFree);
  VariableInfo readable = InfoOf(info);
  readable.name = variable;
  ACCELCAL_RETURN_IF_ERROR(
      CheckReadable(readable, impl_->file_size,
                    info->compression == MAT_COMPRESSION_NONE ? 1 : kZlibExpansion, classes));
  Mat_Rewind(impl_->mat);
  matvar_t* var = Mat_VarRead(impl_->mat, variable.c_str());
  if (var == nullptr || var->data == nullptr || !LastMatioMessage().empty()) {
    if (var != nullptr) Mat_VarFree(var);
    return Status::Error("cannot read " + where +
                         (LastMatioMessage().empty() ? "" : " (" + LastMatioMessage() + ")"));
  }
  const std::unique_ptr<matvar_t, void (*)(matvar_t*)> var_owner(var, Mat_VarFree);
  return CopyValues(var, readable, matrix);
}

Status MatFileReader::ReadAllMatrices(uint64_t max_values, const std::string& oversize_advice,
                                      std::vector<std::pair<std::string, MatMatrix>>* matrices) {
  matrices->clear();
  auto check_size = [&](const VariableInfo& info) {
    uint64_t values = 1;
    for (const uint64_t dimension : info.dims) values *= std::min<uint64_t>(dimension, 1ull << 32);
    if (values <= max_values) return Status::Ok();
    std::string shape;
    for (const uint64_t dimension : info.dims)
      shape += (shape.empty() ? "" : "x") + std::to_string(dimension);
    return Status::Error("variable '" + info.name + "' is " + shape + "; " + oversize_advice);
  };
  if (impl_->mat73) {
    for (const Mat73Variable& candidate : impl_->mat73_variables) {
      ACCELCAL_RETURN_IF_ERROR(check_size(candidate.info));
      MatMatrix matrix;
      ACCELCAL_RETURN_IF_ERROR(ReadMatrix(candidate.info.name, &matrix));
      matrices->emplace_back(candidate.info.name, std::move(matrix));
    }
    return Status::Ok();
  }
  // First pass: headers only, so that nothing large is read.
  std::vector<VariableInfo> infos;
  Mat_Rewind(impl_->mat);
  LastMatioMessage().clear();
  while (matvar_t* info = Mat_VarReadNextInfo(impl_->mat)) {
    const std::unique_ptr<matvar_t, void (*)(matvar_t*)> owner(info, Mat_VarFree);
    infos.push_back(InfoOf(info));
    ACCELCAL_RETURN_IF_ERROR(
        CheckReadable(infos.back(), impl_->file_size,
                      info->compression == MAT_COMPRESSION_NONE ? 1 : kZlibExpansion));
    ACCELCAL_RETURN_IF_ERROR(check_size(infos.back()));
  }
  if (!LastMatioMessage().empty()) {
    return Status::Error("cannot list the variables (" + LastMatioMessage() + ")");
  }
  // Second pass: the data, variable after variable.
  Mat_Rewind(impl_->mat);
  for (const VariableInfo& info : infos) {
    matvar_t* var = Mat_VarReadNext(impl_->mat);
    const std::unique_ptr<matvar_t, void (*)(matvar_t*)> owner(var, Mat_VarFree);
    if (var == nullptr || var->data == nullptr || !LastMatioMessage().empty() ||
        var->name == nullptr || info.name != var->name) {
      return Status::Error("cannot read variable '" + info.name + "'" +
                           (LastMatioMessage().empty() ? "" : " (" + LastMatioMessage() + ")"));
    }
    MatMatrix matrix;
    ACCELCAL_RETURN_IF_ERROR(CopyValues(var, info, &matrix));
    matrices->emplace_back(info.name, std::move(matrix));
  }
  Mat_Rewind(impl_->mat);
  return Status::Ok();
}

Status WriteMatFile(const std::string& path,
                    const std::vector<std::pair<std::string, MatMatrix>>& variables) {
  InstallMatioLogger();
  return WriteAtomicallyWith(path, [&](const std::string& temporary_path) {
    LastMatioMessage().clear();
    mat_t* mat = Mat_CreateVer(temporary_path.c_str(), "MATLAB 5.0 MAT-file, written by accelcal",
                               MAT_FT_MAT5);
    if (mat == nullptr) return Status::Error("cannot create " + path + " " + LastMatioMessage());
    Status status;
    for (const auto& [name, matrix] : variables) {
      size_t dims[2] = {static_cast<size_t>(matrix.rows), static_cast<size_t>(matrix.cols)};
      matvar_t* var =
          Mat_VarCreate(name.c_str(), MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims,
                        const_cast<double*>(matrix.values.data()), MAT_F_DONT_COPY_DATA);
      if (var == nullptr || Mat_VarWrite(mat, var, MAT_COMPRESSION_NONE) != 0) {
        status = Status::Error("cannot write variable '" + name + "' to " + path);
      }
      if (var != nullptr) Mat_VarFree(var);
      if (!status.ok()) break;
    }
    Mat_Close(mat);
    return status;
  });
}

}  // namespace accelcal
