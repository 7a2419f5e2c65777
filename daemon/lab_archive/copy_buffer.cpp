#include "copy_buffer.hpp"

#include <charconv>
#include <cmath>

namespace rig::lab_archive {

void CopyBuffer::separate() {
  if (row_open_) text_ += '\t';
  row_open_ = true;
}

CopyBuffer& CopyBuffer::field(std::string_view text) {
  separate();
  for (const char c : text) {
    switch (c) {
      case '\\':
        text_ += "\\\\";
        break;
      case '\t':
        text_ += "\\t";
        break;
      case '\n':
        text_ += "\\n";
        break;
      case '\r':
        text_ += "\\r";
        break;
      default:
        text_ += c;
    }
  }
  return *this;
}

CopyBuffer& CopyBuffer::field(double value) {
  separate();
  if (std::isnan(value)) {
    text_ += "NaN";
  } else if (std::isinf(value)) {
    text_ += value > 0 ? "Infinity" : "-Infinity";
  } else {
    char digits[32];
    const auto result = std::to_chars(digits, digits + sizeof digits, value);
    text_.append(digits, result.ptr);
  }
  return *this;
}

CopyBuffer& CopyBuffer::field(std::int64_t value) {
  separate();
  char digits[24];
  const auto result = std::to_chars(digits, digits + sizeof digits, value);
  text_.append(digits, result.ptr);
  return *this;
}

CopyBuffer& CopyBuffer::field(const std::optional<double>& value) {
  return value ? field(*value) : null();
}

CopyBuffer& CopyBuffer::null() {
  separate();
  text_ += "\\N";
  return *this;
}

void CopyBuffer::end_row() {
  text_ += '\n';
  row_open_ = false;
  ++rows_;
}

void CopyBuffer::clear() {
  text_.clear();
  row_open_ = false;
  rows_ = 0;
}

}  // namespace rig::lab_archive
