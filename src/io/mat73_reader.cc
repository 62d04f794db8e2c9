#include "io/mat73_reader.h"

#include <fcntl.h>
#include <hdf5.h>
#include <matio.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <string>
#include <vector>

#include "io/mat_integrity.h"

namespace accelcal {
namespace mat_internal {
namespace {

// matio reads version 7.3 files through HDF5, and neither was written for hostile input:
// HDF5's advisories list many crashes and overflows on malformed files, and matio's v7.3
// reader reads attributes of any size into a single int ("FIXME: Check that dataspace is
// scalar", mat73.c). Neither library is built with our sanitizers, so a memory corruption
// would not even be seen, and no check of ours before the read can cover HDF5's whole
// format. A child process therefore reads the file: it opens it with HDF5, reads every
// variable ReadMatrix could return, and sends them through a pipe. If it crashes, hangs or
// runs out of memory, the parent reports one line; nothing of the child's state reaches the
// parent. (Version 7.3 files are rare in the course; one fork per file costs a millisecond.)

constexpr int kMat73ReaderTimeoutSeconds = 120;  // without a byte from the reader
constexpr uint64_t kMaxMessageBytes = 4096;
enum : uint64_t { kRecordVariable = 1, kRecordError = 2, kRecordEnd = 3 };

// HDF5 prints its error stack on stderr at every failed call; the reader keeps stderr for
// its one line. Once per process (the child's is a fresh one).
void SilenceHdf5() {
  static std::once_flag once;
  std::call_once(once, [] { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); });
}

// The innermost (most specific) description on HDF5's error stack, on one line.
std::string Hdf5Error() {
  std::string message;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned, const H5E_error2_t* error, void* data) -> herr_t {
        if (error->desc != nullptr && error->desc[0] != '\0') {
          *static_cast<std::string*>(data) = error->desc;
        }
        return 0;
      },
      &message);
  for (char& c : message) {
    if (std::iscntrl(static_cast<unsigned char>(c))) c = ' ';
  }
  if (message.size() > 200) message = message.substr(0, 200) + "...";
  return message.empty() ? "no reason given" : message;
}

// H5Literate's callback: stops at the first object of the root group whose header HDF5
// cannot read (matio skips it without a word, and the variable seems absent); `data` gets
// the one-line problem.
herr_t FindUnreadableVariable(hid_t group, const char* name, const H5L_info_t*, void* data) {
  H5O_info_t info;
  if (H5Oget_info_by_name2(group, name, &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0) {
    *static_cast<std::string*>(data) =
        (IsIdentifier(name) ? "variable '" + std::string(name) + "'" : std::string("a variable")) +
        " cannot be read (HDF5: " + Hdf5Error() + "); the file is damaged";
    return 1;
  }
  return 0;
}

// Whether the dataset `dataset` stores its values; empty if it does, else the one-line
// problem. HDF5 returns the fill value, zeros, for a dataset whose storage was never written or
// whose address was lost, without an error. H5Dget_space_status tells the two apart only for a
// contiguous or compact dataset, whose storage is one block: ALLOCATED or NOT_ALLOCATED. A
// chunked one (MATLAB's -v7.3 writes its variables chunked and compressed) is PART_ALLOCATED
// whenever its stored bytes differ from its nominal size, that is, whenever it is compressed or
// its last chunks overhang its dimensions, however many of its chunks are stored; so a chunked
// dataset is judged by its chunk index instead, which H5Dget_num_chunks walks whole (a damaged
// index fails here, named as such, rather than read as zeros). No chunk stored: damaged, as an
// unallocated contiguous dataset. Some chunks stored: a writer may legitimately write part of a
// chunked dataset (MATLAB's matfile writes a slice of a variable), and HDF5, MATLAB and we read the
// others as the dataset's fill value; unless it has none, when HDF5 leaves them undefined.
std::string CheckStoredData(hid_t dataset, const std::string& what) {
  const std::string damaged =
      what + " has no stored data (HDF5 would return zeros); the file is damaged";
  const hid_t space = H5Dget_space(dataset);
  const int rank = space >= 0 ? H5Sget_simple_extent_ndims(space) : -1;
  std::vector<hsize_t> dims(static_cast<size_t>(std::max(rank, 0)));
  const bool shaped = rank >= 0 && H5Sget_simple_extent_dims(space, dims.data(), nullptr) == rank;
  const hssize_t points = space >= 0 ? H5Sget_simple_extent_npoints(space) : -1;
  if (space >= 0) H5Sclose(space);
  if (points == 0) return "";
  if (!shaped || points < 0) return damaged;
  // A failed query (the dataset's storage index is damaged) is told apart from an absent one.
  const auto unreadable = [&what] {
    return what + " has data HDF5 cannot locate (" + Hdf5Error() + "); the file is damaged";
  };
  H5D_space_status_t status = H5D_SPACE_STATUS_ERROR;
  if (H5Dget_space_status(dataset, &status) < 0) return unreadable();
  if (status == H5D_SPACE_STATUS_NOT_ALLOCATED) return damaged;
  const hid_t properties = H5Dget_create_plist(dataset);
  if (properties < 0) return damaged;
  const H5D_layout_t layout = H5Pget_layout(properties);
  std::vector<hsize_t> chunk(dims.size());
  const bool chunked =
      layout == H5D_CHUNKED && H5Pget_chunk(properties, rank, chunk.data()) == rank;
  H5D_fill_value_t fill = H5D_FILL_VALUE_ERROR;
  const bool has_fill = H5Pfill_value_defined(properties, &fill) >= 0 &&
                        (fill == H5D_FILL_VALUE_DEFAULT || fill == H5D_FILL_VALUE_USER_DEFINED);
  H5Pclose(properties);
  if (layout != H5D_CHUNKED) return status == H5D_SPACE_STATUS_ALLOCATED ? "" : damaged;
  hsize_t expected = 1;
  for (size_t k = 0; chunked && k < dims.size(); ++k) {
    if (chunk[k] == 0) return damaged;
    expected *= (dims[k] + chunk[k] - 1) / chunk[k];
  }
  // HDF5 1.10 takes the dataset's own dataspace for the whole of it, not H5S_ALL.
  hsize_t stored = 0;
  const hid_t whole = H5Dget_space(dataset);
  const herr_t counted = chunked && whole >= 0 ? H5Dget_num_chunks(dataset, whole, &stored) : -1;
  if (whole >= 0) H5Sclose(whole);
  if (counted < 0) return unreadable();
  if (stored == 0) return damaged;
  if (stored > expected) {
    return what + " stores " + std::to_string(stored) + " chunks where its dimensions hold " +
           std::to_string(expected) + "; the file is damaged";
  }
  if (stored < expected && !has_fill) {
    return what + " stores " + std::to_string(stored) + " of its " + std::to_string(expected) +
           " chunks and has no fill value for the others (HDF5 would return undefined values); "
           "the file is damaged";
  }
  return "";
}

// H5Ovisit's callback, for every group and dataset of the file, nested ones (struct fields,
// cell elements) included: stops at the first that matio would misread; `data` gets the
// one-line problem. matio reads each of four attributes into a single number ("FIXME: Check
// that dataspace is scalar", mat73.c): a larger one overwrites its memory (an int32
// MATLAB_global of 4000 values crashes it). And HDF5 returns its fill value, zeros, for a
// dataset whose storage was never written or whose address was lost.
herr_t CheckHdf5Object(hid_t root, const char* path, const H5O_info_t* info, void* data) {
  if (info->type != H5O_TYPE_GROUP && info->type != H5O_TYPE_DATASET) return 0;
  std::string printable = path;
  for (char& c : printable) {
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  }
  if (printable.size() > 64) printable = printable.substr(0, 64) + "...";
  const std::string what =
      IsIdentifier(path) ? "variable '" + printable + "'" : "the HDF5 object '" + printable + "'";
  std::string* problem = static_cast<std::string*>(data);
  const hid_t object = H5Oopen(root, path, H5P_DEFAULT);
  if (object < 0) {
    *problem = what + " cannot be read (HDF5: " + Hdf5Error() + "); the file is damaged";
    return 1;
  }
  for (const char* attribute :
       {"MATLAB_global", "MATLAB_int_decode", "MATLAB_empty", "MATLAB_sparse"}) {
    if (H5Aexists(object, attribute) <= 0) continue;
    const hid_t opened = H5Aopen(object, attribute, H5P_DEFAULT);
    const hid_t space = opened >= 0 ? H5Aget_space(opened) : -1;
    const hssize_t values = space >= 0 ? H5Sget_simple_extent_npoints(space) : -1;
    if (space >= 0) H5Sclose(space);
    if (opened >= 0) H5Aclose(opened);
    if (values != 1) {
      *problem = what + " has a " + attribute + " attribute of " + std::to_string(values) +
                 " values where MATLAB writes one; the file is damaged";
      break;
    }
  }
  if (problem->empty() && info->type == H5O_TYPE_DATASET) *problem = CheckStoredData(object, what);
  H5Oclose(object);
  return problem->empty() ? 0 : 1;
}

// In the child: opens the file with HDF5 itself before matio does, so that a failure is
// named in HDF5's words (matio takes a file HDF5 cannot open for a file without variables,
// and a variable it cannot read for an absent one), then checks every object as
// CheckHdf5Object does.
Status CheckHdf5File(const std::string& path) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) {
    return Status::Error("HDF5 cannot open the version 7.3 file (" + Hdf5Error() +
                         "); the file is damaged");
  }
  std::string problem;
  hsize_t index = 0;
  const herr_t listed =
      H5Literate(file, H5_INDEX_NAME, H5_ITER_NATIVE, &index, FindUnreadableVariable, &problem);
  if (listed < 0) {
    const std::string why = Hdf5Error();
    H5Fclose(file);
    return Status::Error("HDF5 cannot list the variables of the version 7.3 file (" + why +
                         "); the file is damaged");
  }
  if (!problem.empty()) {
    H5Fclose(file);
    return Status::Error(problem);
  }
  const herr_t visited =
      H5Ovisit2(file, H5_INDEX_NAME, H5_ITER_NATIVE, CheckHdf5Object, &problem, H5O_INFO_BASIC);
  const std::string why = visited < 0 ? Hdf5Error() : "";
  H5Fclose(file);
  if (!problem.empty()) return Status::Error(problem);
  if (visited < 0) {
    return Status::Error("HDF5 cannot read the objects of the version 7.3 file (" + why +
                         "); the file is damaged");
  }
  return Status::Ok();
}

class PipeWriter {
 public:
  explicit PipeWriter(int fd) : fd_(fd) {}
  void Bytes(const void* data, size_t count) {
    const char* at = static_cast<const char*>(data);
    while (ok_ && count > 0) {
      const ssize_t written = write(fd_, at, count);
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) {
        ok_ = false;
        break;
      }
      at += written;
      count -= static_cast<size_t>(written);
    }
  }
  void Number(uint64_t value) { Bytes(&value, sizeof(value)); }
  void Text(const std::string& text) {
    Number(text.size());
    Bytes(text.data(), text.size());
  }
  bool ok() const { return ok_; }

 private:
  int fd_;
  bool ok_ = true;
};

class PipeReader {
 public:
  PipeReader(int fd, int timeout_seconds) : fd_(fd), timeout_ms_(timeout_seconds * 1000) {}
  // False at the end of the stream, on an error, or after the timeout without a byte.
  bool Bytes(void* out, size_t count) {
    char* at = static_cast<char*>(out);
    while (count > 0) {
      pollfd ready{fd_, POLLIN, 0};
      const int polled = poll(&ready, 1, timeout_ms_);
      if (polled < 0 && errno == EINTR) continue;
      if (polled == 0) timed_out_ = true;
      if (polled <= 0) return false;
      const ssize_t got = read(fd_, at, count);
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) return false;
      at += got;
      count -= static_cast<size_t>(got);
    }
    return true;
  }
  bool Number(uint64_t* value) { return Bytes(value, sizeof(*value)); }
  bool Text(std::string* text) {
    uint64_t size = 0;
    if (!Number(&size) || size > kMaxMessageBytes) return false;
    text->resize(size);
    return Bytes(&(*text)[0], size);
  }
  bool timed_out() const { return timed_out_; }

 private:
  int fd_;
  int timeout_ms_;
  bool timed_out_ = false;
};

// In the child: reads the file and sends every variable's info and, for those
// ReadNumericMatrix can return, its values; or one error record.
void SendMat73Variables(const std::string& path, uint64_t file_size, PipeWriter* out) {
  InstallMatioLogger();
  SilenceHdf5();
  const auto fail = [&](const std::string& message) {
    out->Number(kRecordError);
    out->Text(message);
  };
  const Status hdf5 = CheckHdf5File(path);
  if (!hdf5.ok()) return fail(hdf5.message());
  LastMatioMessage().clear();
  mat_t* mat = Mat_Open(path.c_str(), MAT_ACC_RDONLY);
  if (mat == nullptr) {
    return fail("not a readable MAT file" +
                (LastMatioMessage().empty() ? "" : " (" + LastMatioMessage() + ")") +
                "; save it from MATLAB/Octave with save -v7 or -v6");
  }
  std::vector<VariableInfo> infos;
  size_t longest_name = 0;
  while (matvar_t* var = Mat_VarReadNextInfo(mat)) {
    if (var->name != nullptr) infos.push_back(InfoOf(var));
    if (var->name != nullptr) longest_name = std::max(longest_name, infos.back().name.size());
    Mat_VarFree(var);
  }
  if (longest_name > kMaxMessageBytes) {
    Mat_Close(mat);
    return fail("a variable's name is " + std::to_string(longest_name) +
                " bytes long (MATLAB allows 63); the file is damaged");
  }
  if (!LastMatioMessage().empty()) {
    Mat_Close(mat);
    return fail("cannot list the variables (" + LastMatioMessage() + ")");
  }
  for (const VariableInfo& info : infos) {
    out->Number(kRecordVariable);
    out->Text(info.name);
    out->Number(static_cast<uint64_t>(info.class_type));
    out->Number(info.is_complex ? 1 : 0);
    out->Number(info.is_logical ? 1 : 0);
    out->Number(info.dims.size());
    for (uint64_t dimension : info.dims) out->Number(dimension);
    out->Number(info.element_bytes);
    out->Number(info.fields.size());
    for (const std::string& field : info.fields) out->Text(field);
    if (!CheckReadable(info, file_size, kZlibExpansion, MatClasses::kNumeric).ok()) {
      out->Number(kValuesNone);
      continue;
    }
    LastMatioMessage().clear();
    matvar_t* var = Mat_VarRead(mat, info.name.c_str());
    MatMatrix matrix;
    if (var == nullptr || var->data == nullptr || !LastMatioMessage().empty()) {
      out->Number(kValuesFailed);
      out->Text(LastMatioMessage().substr(0, kMaxMessageBytes));
    } else if (const Status copied = CopyValues(var, info, &matrix); !copied.ok()) {
      out->Number(kValuesRefused);
      out->Text(copied.message().substr(0, kMaxMessageBytes));
    } else {
      out->Number(kValuesRead);
      out->Bytes(matrix.values.data(), matrix.values.size() * sizeof(double));
    }
    if (var != nullptr) Mat_VarFree(var);
  }
  Mat_Close(mat);
  out->Number(kRecordEnd);
}

// In the parent: what the child sent, checked as input (a number out of range ends it).
Status ReceiveMat73Variables(PipeReader* in, uint64_t file_size,
                             std::vector<Mat73Variable>* variables) {
  const Status broken = Status::Error(
      "HDF5 could not read the version 7.3 file (its reader stopped without an "
      "answer); the file is damaged: open it in MATLAB and save it again");
  variables->clear();
  while (true) {
    uint64_t kind = 0;
    if (!in->Number(&kind)) return broken;
    if (kind == kRecordEnd) return Status::Ok();
    if (kind == kRecordError) {
      std::string message;
      return in->Text(&message) ? Status::Error(message) : broken;
    }
    if (kind != kRecordVariable || variables->size() > file_size) return broken;
    Mat73Variable variable;
    VariableInfo& info = variable.info;
    uint64_t class_type = 0, is_complex = 0, is_logical = 0, rank = 0;
    if (!in->Text(&info.name) || !in->Number(&class_type) || !in->Number(&is_complex) ||
        !in->Number(&is_logical) || !in->Number(&rank) || rank > kMaxRank) {
      return broken;
    }
    info.class_type = static_cast<int>(std::min<uint64_t>(class_type, 255));
    info.is_complex = is_complex != 0;
    info.is_logical = is_logical != 0;
    info.dims.resize(rank);
    for (uint64_t& dimension : info.dims) {
      if (!in->Number(&dimension)) return broken;
    }
    uint64_t fields = 0;
    if (!in->Number(&info.element_bytes) || !in->Number(&fields) || fields > kMaxListedFields) {
      return broken;
    }
    info.fields.resize(fields);
    for (std::string& field : info.fields) {
      if (!in->Text(&field)) return broken;
    }
    if (!in->Number(&variable.values_kind)) return broken;
    if (variable.values_kind == kValuesFailed || variable.values_kind == kValuesRefused) {
      if (!in->Text(&variable.read_error)) return broken;
    } else if (variable.values_kind == kValuesRead) {
      if (!CheckReadable(info, file_size, kZlibExpansion, MatClasses::kNumeric).ok()) return broken;
      try {
        variable.values.resize(info.dims[0] * info.dims[1]);
      } catch (const std::bad_alloc&) {
        return Status::Error("not enough memory for variable '" + info.name + "' (" +
                             std::to_string(info.dims[0]) + "x" + std::to_string(info.dims[1]) +
                             "); free memory or raise the limit (ulimit -v)");
      }
      if (!in->Bytes(variable.values.data(), variable.values.size() * sizeof(double))) {
        return broken;
      }
    } else if (variable.values_kind != kValuesNone) {
      return broken;
    }
    variables->push_back(std::move(variable));
  }
}

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ACCELCAL_ADDRESS_SANITIZER 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define ACCELCAL_ADDRESS_SANITIZER 1
#endif

// In the child: bounds its address space to what it has, plus twice the largest variable the
// file can hold (matio's copy and ours) and 1 GiB for HDF5, so that a damaged file asking
// HDF5 for absurd amounts fails an allocation in the child rather than draw the OOM killer.
// Not under AddressSanitizer, whose shadow memory reserves terabytes of address space.
void LimitReaderMemory(uint64_t file_size) {
#ifndef ACCELCAL_ADDRESS_SANITIZER
  unsigned long long pages = 0;
  FILE* statm = std::fopen("/proc/self/statm", "r");
  if (statm == nullptr) return;
  const bool parsed = std::fscanf(statm, "%llu", &pages) == 1;
  std::fclose(statm);
  if (!parsed) return;
  const uint64_t largest = std::min<uint64_t>(file_size, 1ull << 30) * kZlibExpansion;
  const uint64_t limit =
      pages * static_cast<uint64_t>(sysconf(_SC_PAGESIZE)) + (1ull << 30) + 2 * largest;
  rlimit current;
  if (getrlimit(RLIMIT_AS, &current) == 0 &&
      (current.rlim_cur == RLIM_INFINITY || current.rlim_cur > limit)) {
    current.rlim_cur = limit;
    setrlimit(RLIMIT_AS, &current);
  }
#else
  (void)file_size;
#endif
}

}  // namespace

Status ReadMat73InChild(const std::string& path, uint64_t file_size,
                        std::vector<Mat73Variable>* variables) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) {
    return Status::Error(std::string("cannot start a reader for the version 7.3 file (") +
                         std::strerror(errno) + "); free some processes or files and retry");
  }
  const pid_t child = fork();
  if (child < 0) {
    const int error = errno;
    close(fds[0]);
    close(fds[1]);
    return Status::Error(std::string("cannot start a reader for the version 7.3 file (") +
                         std::strerror(error) + "); free some processes or memory and retry");
  }
  if (child == 0) {
    // Default dispositions, not the parent's cleanup handlers; no blocked signals; no life
    // beyond the parent's. _exit: no atexit handlers, no flushing of the parent's buffers.
    close(fds[0]);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    for (int signal_number : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) signal(signal_number, SIG_DFL);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    LimitReaderMemory(file_size);
    PipeWriter out(fds[1]);
    SendMat73Variables(path, file_size, &out);
    _exit(out.ok() ? 0 : 1);
  }
  close(fds[1]);
  PipeReader in(fds[0], kMat73ReaderTimeoutSeconds);
  const Status status = ReceiveMat73Variables(&in, file_size, variables);
  close(fds[0]);
  if (!status.ok()) kill(child, SIGKILL);  // it may be waiting to write, or hung
  int wait_status = 0;
  while (waitpid(child, &wait_status, 0) < 0 && errno == EINTR) {
  }
  if (in.timed_out()) {
    return Status::Error("HDF5 read nothing for " + std::to_string(kMat73ReaderTimeoutSeconds) +
                         " s; the file may be damaged: open it in MATLAB and save it again");
  }
  if (!status.ok() && WIFSIGNALED(wait_status) && WTERMSIG(wait_status) != SIGKILL) {
    return Status::Error("HDF5 could not read the version 7.3 file (its reader died of signal " +
                         std::to_string(WTERMSIG(wait_status)) + ", " +
                         strsignal(WTERMSIG(wait_status)) +
                         "); the file is damaged: open it in MATLAB and save it again");
  }
  return status;
}

}  // namespace mat_internal
}  // namespace accelcal
