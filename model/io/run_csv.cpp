#include "run_csv.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace rig::model {
namespace {

// A metadata value is one line: a newline in a run's notes must not end it (or start a
// data row). Escaped as \n, \r and \\; any other backslash is kept as it is.
std::string escape_meta(const std::string& value) {
  std::string out;
  out.reserve(value.size());
  for (const char c : value) {
    if (c == '\n')
      out += "\\n";
    else if (c == '\r')
      out += "\\r";
    else if (c == '\\')
      out += "\\\\";
    else
      out.push_back(c);
  }
  return out;
}

std::string unescape_meta(const std::string& value) {
  std::string out;
  out.reserve(value.size());
  for (std::size_t i = 0; i < value.size(); ++i) {
    const char next = i + 1 < value.size() ? value[i + 1] : '\0';
    if (value[i] == '\\' && (next == 'n' || next == 'r' || next == '\\')) {
      out.push_back(next == 'n' ? '\n' : (next == 'r' ? '\r' : '\\'));
      ++i;
    } else {
      out.push_back(value[i]);
    }
  }
  return out;
}

std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    std::string field =
        line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const auto first = field.find_first_not_of(' ');
    const auto last = field.find_last_not_of(' ');
    fields.push_back(first == std::string::npos ? std::string()
                                                : field.substr(first, last - first + 1));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

struct Columns {
  int t = -1;
  int x = -1;
  int force = -1;
  std::vector<int> extra;
};

class Parser {
 public:
  Parser(std::istream& in, std::string name) : in_(in), name_(std::move(name)) {
    run_.source = name_;
  }

  RunData parse() {
    std::string line;
    bool header_seen = false;
    while (std::getline(in_, line)) {
      ++line_no_;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line_no_ == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 BOM
      if (line.empty()) continue;
      if (!header_seen && line[0] == '#') {
        parse_meta(line);
      } else if (!header_seen) {
        parse_header(line);
        header_seen = true;
      } else {
        parse_row(line);
      }
    }
    if (!header_seen) fail(line_no_, "no header row (t_s,x_mm,force_N,...)");
    if (run_.t_s.empty()) fail(line_no_, "no data rows");
    for (const char* key : {"iop_mmHg", "velocity_mm_s"}) {
      if (!run_.number(key)) {
        run_.warnings.push_back(name_ + ": no numeric '" + key +
                                "' metadata: left out of analyses that need it");
      }
    }
    return std::move(run_);
  }

 private:
  [[noreturn]] void fail(std::size_t line, const std::string& what) const {
    throw RunCsvError(name_ + ":" + std::to_string(line) + ": " + what);
  }

  // "# key: value" by hand: std::regex recurses per character and overflows the stack on
  // long lines. Values are unescaped (\n, \r, \\), as write_run_csv escapes them.
  void parse_meta(const std::string& line) {
    std::size_t i = 1;
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t key_begin = i;
    const auto is_key_char = [](char c, bool first) {
      return std::isalpha(static_cast<unsigned char>(c)) != 0 || c == '_' ||
             (!first && std::isdigit(static_cast<unsigned char>(c)) != 0);
    };
    while (i < line.size() && is_key_char(line[i], i == key_begin)) ++i;
    const std::size_t key_end = i;
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (key_end == key_begin || i >= line.size() || line[i] != ':')
      fail(line_no_, "metadata line is not '# key: value'");
    ++i;
    if (i < line.size() && line[i] == ' ') ++i;
    std::string value = unescape_meta(line.substr(i));
    while (!value.empty() && value.back() == ' ') value.pop_back();
    run_.meta.emplace_back(line.substr(key_begin, key_end - key_begin), value);
  }

  void parse_header(const std::string& line) {
    header_ = split_commas(line);
    for (std::size_t i = 0; i < header_.size(); ++i) {
      const std::string& name = header_[i];
      if (name.empty())
        fail(line_no_, "empty column name in the header (column " + std::to_string(i + 1) + ")");
      for (std::size_t j = 0; j < i; ++j) {
        if (header_[j] == name) fail(line_no_, "column '" + name + "' appears twice");
      }
      const int index = static_cast<int>(i);
      if (name == "t_s")
        columns_.t = index;
      else if (name == "x_mm")
        columns_.x = index;
      else if (name == "force_N")
        columns_.force = index;
      else {
        columns_.extra.push_back(index);
        run_.channels.push_back(Channel{name, {}});
      }
    }
    for (const auto& [col, name] : {std::pair{columns_.t, "t_s"}, std::pair{columns_.x, "x_mm"},
                                    std::pair{columns_.force, "force_N"}}) {
      if (col < 0)
        fail(line_no_, std::string("required column '") + name + "' is missing from the header");
    }
  }

  double number(const std::vector<std::string>& fields, int col) const {
    const std::string& text = fields[static_cast<std::size_t>(col)];
    double value = 0.0;
    const char* end = text.data() + text.size();
    const auto result = std::from_chars(text.data(), end, value);
    if (text.empty() || result.ec != std::errc{} || result.ptr != end || !std::isfinite(value)) {
      fail(line_no_, "column '" + header_[static_cast<std::size_t>(col)] + "': '" + text +
                         "' is not a number");
    }
    return value;
  }

  void parse_row(const std::string& line) {
    if (line[0] == '#') fail(line_no_, "metadata line after the header");
    const std::vector<std::string> fields = split_commas(line);
    if (fields.size() != header_.size()) {
      fail(line_no_, "expected " + std::to_string(header_.size()) + " fields, found " +
                         std::to_string(fields.size()));
    }
    const double t = number(fields, columns_.t);
    if (!run_.t_s.empty() && t < run_.t_s.back()) {
      fail(line_no_, "column 't_s': time goes backwards (" +
                         fields[static_cast<std::size_t>(columns_.t)] + " s)");
    }
    run_.t_s.push_back(t);
    run_.x_mm.push_back(number(fields, columns_.x));
    run_.force_N.push_back(number(fields, columns_.force));
    for (std::size_t i = 0; i < columns_.extra.size(); ++i) {
      run_.channels[i].values.push_back(number(fields, columns_.extra[i]));
    }
  }

  std::istream& in_;
  std::string name_;
  std::size_t line_no_ = 0;
  std::vector<std::string> header_;
  Columns columns_;
  RunData run_;
};

}  // namespace

RunData read_run_csv(std::istream& in, const std::string& name) {
  return Parser(in, name).parse();
}

RunData read_run_csv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RunCsvError(path + ": cannot open");
  return read_run_csv(in, path);
}

void write_run_csv(const RunData& run, std::ostream& out) {
  for (const auto& [key, value] : run.meta)
    out << "# " << key << ": " << escape_meta(value) << "\n";
  out << "t_s,x_mm,force_N";
  for (const auto& c : run.channels) out << "," << c.name;
  out << "\n";
  char buffer[64];
  for (std::size_t i = 0; i < run.size(); ++i) {
    std::snprintf(buffer, sizeof buffer, "%.6f,%.5f,%.6f", run.t_s[i], run.x_mm[i], run.force_N[i]);
    out << buffer;
    for (const auto& c : run.channels) {
      std::snprintf(buffer, sizeof buffer, ",%.6g", c.values[i]);
      out << buffer;
    }
    out << "\n";
  }
}

void write_run_csv(const RunData& run, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw RunCsvError(path + ": cannot write");
  write_run_csv(run, out);
  if (!out) throw RunCsvError(path + ": write failed");
}

}  // namespace rig::model
