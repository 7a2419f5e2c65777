#pragma once
// Splits a fuzz input into the pieces a structured target needs: small numbers, raw 8-byte
// words, and length-prefixed byte strings that may be stretched to tens of KB (a long value
// costs the fuzzer a few bytes, so long inputs are tried at every size). Past the end of the
// input every read gives zeros or empty strings, so any input is a complete description.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace rig::fuzz {

class FuzzByteReader {
 public:
  FuzzByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  bool empty() const { return at_ >= size_; }

  std::uint8_t byte() { return at_ < size_ ? data_[at_++] : 0; }

  // 0 .. bound-1 (bound >= 1).
  std::size_t below(std::size_t bound) { return byte() % bound; }

  // Eight raw bytes: any bit pattern, NaN and infinities included.
  std::uint64_t word() {
    std::uint64_t value = 0;
    const std::size_t n = std::min<std::size_t>(sizeof value, size_ - std::min(at_, size_));
    if (n > 0) std::memcpy(&value, data_ + at_, n);
    at_ += n;
    return value;
  }

  // Up to 255 bytes as given: invalid UTF-8, NULs and control characters included.
  std::string bytes() {
    // The length byte first: in one call's arguments, gcc may compute the room left before
    // byte() has moved past it (read one byte beyond the input, found by fuzz_replay).
    const std::size_t wanted = byte();
    const std::size_t length = std::min<std::size_t>(wanted, size_ - std::min(at_, size_));
    std::string out(reinterpret_cast<const char*>(data_ + at_), length);
    at_ += length;
    return out;
  }

  // bytes(), repeated up to max_bytes in all: the long values of a reader's worst case.
  std::string stretched(std::size_t max_bytes) {
    const std::size_t times = 1 + static_cast<std::size_t>(byte()) * 64;  // up to ~16,000 repeats
    const std::string piece = bytes();
    if (piece.empty()) return std::string(std::min(times, max_bytes), 'x');
    std::string out;
    while (out.size() + piece.size() <= max_bytes && times * piece.size() > out.size())
      out += piece;
    return out;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
};

}  // namespace rig::fuzz
