#ifndef ACCELCAL_IO_INPUT_FILE_H_
#define ACCELCAL_IO_INPUT_FILE_H_

// What every reader checks before it reads: that the path names a regular file (not a
// folder, a device such as /dev/zero, a FIFO or a socket, whose size says nothing about
// what a read would return) no larger than the reader's cap, and that reading it whole
// either succeeds or fails with a message; a memory failure is an error, never a
// truncated read. Messages carry no file name (callers add it with Status::WithContext).

#include <sys/types.h>

#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"

namespace accelcal {

// read(2) of up to `size` bytes, retried when a signal interrupts it.
ssize_t ReadSome(int fd, char* data, size_t size);

// What stat says of a file's content: its device, inode, size and modification and status-change
// times (ns). Two equal identities: nothing wrote to the file in between (to the file system's
// clock, nanoseconds on ext4, xfs, btrfs and tmpfs).
struct FileIdentity {
  uint64_t device = 0;
  uint64_t inode = 0;
  uint64_t size = 0;
  int64_t modified_ns = 0;
  int64_t changed_ns = 0;
  bool operator==(const FileIdentity& other) const;
  bool operator!=(const FileIdentity& other) const { return !(*this == other); }
};

Status IdentifyFile(const std::string& path, FileIdentity* identity);
Status IdentifyOpenFile(int fd, FileIdentity* identity);

// A file that changed while it was read, from its identity when opened (`before`) to the end of
// the reading (`after`): one line saying so (a logger still writing it) and what to do. No file
// name: callers add it.
Status FileChangedWhileRead(const FileIdentity& before, const FileIdentity& after);

// The bytes a run parsed of each input file, so that the provenance's checksum
// (io/provenance.h, HashInputFile) covers exactly them, not the file as it is when the checksum is
// taken (a logger still appending in between: the result from 30,424 samples, the checksum of
// more). A reader that parses a whole file computes the SHA-256 of the very bytes it parsed as it
// reads them (ReadInputFile, ReadInputText, io/line_stream.h), checks that the file did not change
// from its opening to its end, and records it here by the path it was given; a file read twice in
// a run must hold the same bytes both times, and a checksum taken later is that record, while the
// file's identity is unchanged. Off until a binary turns it on (InitProblem does): a library user
// may rewrite a file between two readings.
struct InputRead {
  uint64_t bytes = 0;
  std::string sha256;  // of those bytes, 64 lowercase hex digits
  FileIdentity identity;
};

void StartRecordingInputReads();  // also forgets any record
bool RecordingInputReads();

// Records `read` for `path`; fails when the run read `path` before with other bytes (the file
// changed between two readings of one run: a checksum and the parse, or two parses).
Status RecordInputRead(const std::string& path, const InputRead& read);
// The record of `path`, if the run read it.
bool FindInputRead(const std::string& path, InputRead* read);

// An input given as a folder whose files a reader chose (a ROS 2 bag: its .db3 files and
// metadata.yaml): each file with the suffix its role takes in the provenance ("" for the main
// one, "_part_2", "_metadata"). Recorded by the reader while a run records; the provenance
// (DescribeMeasuredData) then lists the files, by role + suffix, instead of the folder.
struct InputFolderPart {
  std::string role_suffix;
  std::string path;
};
void RecordInputFolder(const std::string& folder, const std::vector<InputFolderPart>& parts);
bool FindInputFolder(const std::string& folder, std::vector<InputFolderPart>* parts);

// Reads `path` whole, in pieces, through SHA-256 (any size, bounded memory), checking that its
// identity did not change while it was read.
Status HashFile(const std::string& path, InputRead* read);

// Caps on what a reader takes whole, with the reason each is generous.
// A .mat file is read into memory by matio; 4 GiB is 5e8 doubles, far beyond any test.
constexpr uint64_t kMaxMatFileBytes = 4ull << 30;
// A run or landmark CSV is held in memory as parsed numbers (3 per row).
constexpr uint64_t kMaxCsvFileBytes = 2ull << 30;
// datos.txt and scenario JSON are a few lines.
constexpr uint64_t kMaxConditionsFileBytes = 1ull << 20;

// Fails unless `path` is a regular file of at most `max_bytes` bytes; `size` gets its size.
// `what` names the kind of file in the message ("a MAT file", "a CSV file").
Status CheckInputFile(const std::string& path, uint64_t max_bytes, const std::string& what,
                      uint64_t* size);

// CheckInputFile, then reads the whole file into `contents`. A short read, an I/O error or
// a failed allocation is an error.
Status ReadInputFile(const std::string& path, uint64_t max_bytes, const std::string& what,
                     std::string* contents);

// ReadInputFile for a text file (CSV, datos.txt, JSON): before the whole file is read, its
// first 64 KiB must hold no NUL byte, so that a binary or sparse file (2 GB of zeros) is
// refused at once instead of being read whole and then parsed. Both refuse a file that changed
// while it was read, and record what they read (RecordInputRead) when a run records.
Status ReadInputText(const std::string& path, uint64_t max_bytes, const std::string& what,
                     std::string* contents);

}  // namespace accelcal

#endif  // ACCELCAL_IO_INPUT_FILE_H_
