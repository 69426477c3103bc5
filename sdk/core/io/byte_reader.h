// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Private to sdk/core/io: bounds-checked reading of little/big-endian binary data in memory.
// Callers check remaining() before a run of reads (one check per element); the typed reads
// themselves also refuse to run past the end and return false instead.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "core/namespace.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

inline bool host_is_little_endian() {
  const uint16_t probe = 1;
  uint8_t first;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size, size_t offset, bool little_endian)
      : data_(data), size_(size), pos_(offset), swap_(little_endian != host_is_little_endian()) {}

  size_t offset() const { return pos_; }
  size_t remaining() const { return size_ - pos_; }

  bool skip(uint64_t bytes) {
    if (bytes > remaining()) return false;
    pos_ += static_cast<size_t>(bytes);
    return true;
  }

  // Reads a value of `size` bytes (1, 2, 4 or 8) into `out` in host byte order.
  bool read_raw(void* out, size_t size) {
    if (size > remaining()) return false;
    uint8_t tmp[8];
    std::memcpy(tmp, data_ + pos_, size);
    if (swap_)
      for (size_t i = 0; i < size / 2; ++i) {
        const uint8_t t = tmp[i];
        tmp[i] = tmp[size - 1 - i];
        tmp[size - 1 - i] = t;
      }
    std::memcpy(out, tmp, size);
    pos_ += size;
    return true;
  }

  template <class T>
  bool read(T& value) {
    return read_raw(&value, sizeof(T));
  }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_;
  bool swap_;
};

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
