#ifndef ACCELCAL_COMMON_SHA256_H_
#define ACCELCAL_COMMON_SHA256_H_

// SHA-256 (FIPS 180-4), for the checksums every output gives of the files it was computed
// from: a reader can tell, with `sha256sum`, whether a result belongs to the file in hand.
//
//   Sha256 hash;
//   hash.Update(bytes, size);   // any number of times
//   std::string hex = hash.HexDigest();   // 64 lowercase hex digits

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace accelcal {

class Sha256 {
 public:
  Sha256();
  void Update(const void* data, size_t size);
  // The digest of everything given to Update; the object is spent afterwards.
  std::string HexDigest();

 private:
  void Compress(const uint8_t* block);

  std::array<uint32_t, 8> state_;
  std::array<uint8_t, 64> block_;
  size_t block_size_ = 0;
  uint64_t total_bytes_ = 0;
};

// The digest of a string's bytes.
std::string Sha256Hex(const std::string& bytes);

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_SHA256_H_
