#include "cli_context.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>

namespace rig::cli {

ApiClient CliContext::client() const {
  std::string token;
  if (!token_file.empty()) {
    std::ifstream in(token_file);
    if (!in) throw ApiClientError("--token-file " + token_file + ": cannot read it");
    std::getline(in, token);
  }
  return ApiClient(api_url, token);
}

void print_table(const std::vector<std::string>& header, const Rows& rows) {
  std::vector<std::size_t> width(header.size());
  for (std::size_t c = 0; c < header.size(); ++c) width[c] = header[c].size();
  for (const auto& row : rows) {
    for (std::size_t c = 0; c < row.size() && c < width.size(); ++c)
      width[c] = std::max(width[c], row[c].size());
  }
  auto line = [&](const std::vector<std::string>& cells) {
    for (std::size_t c = 0; c < cells.size(); ++c) {
      std::cout << cells[c]
                << std::string(width[c] - cells[c].size() + (c + 1 < cells.size() ? 2 : 0), ' ');
    }
    std::cout << "\n";
  };
  line(header);
  for (const auto& row : rows) line(row);
}

void print_pairs(const std::vector<std::pair<std::string, std::string>>& pairs) {
  std::size_t width = 0;
  for (const auto& [k, v] : pairs) width = std::max(width, k.size());
  for (const auto& [k, v] : pairs)
    std::cout << k << std::string(width - k.size() + 2, ' ') << v << "\n";
}

std::string fixed(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

nlohmann::json parse_reply(const HttpReply& reply, const std::string& what) {
  nlohmann::json j = nlohmann::json::parse(reply.body, nullptr, false);
  if (j.is_discarded())
    throw ApiClientError(what + ": rigd answered HTTP " + std::to_string(reply.status) +
                         " without JSON");
  return j;
}

}  // namespace rig::cli
