#pragma once
// Rows in PostgreSQL's COPY text format: tab-separated fields, one row a line, \N for NULL,
// doubles written shortest-exact (they read back bit for bit).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace rig::lab_archive {

class CopyBuffer {
 public:
  CopyBuffer& field(std::string_view text);
  CopyBuffer& field(double value);
  CopyBuffer& field(std::int64_t value);
  CopyBuffer& field(const std::optional<double>& value);
  CopyBuffer& null();
  void end_row();
  const std::string& text() const { return text_; }
  std::int64_t rows() const { return rows_; }
  void clear();

 private:
  void separate();
  std::string text_;
  bool row_open_ = false;
  std::int64_t rows_ = 0;
};

}  // namespace rig::lab_archive
