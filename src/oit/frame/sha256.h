// SHA-256 (FIPS 180-4), for the hashes that guard reference images.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace oitref::util {

class Sha256 {
 public:
  Sha256();
  void update(const void* data, size_t size);
  std::string hex();  // finishes the hash; lower-case hex digest

 private:
  void block(const uint8_t* p);
  uint32_t h_[8];
  uint8_t buffer_[64];
  size_t buffered_ = 0;
  uint64_t length_ = 0;
};

}  // namespace oitref::util
