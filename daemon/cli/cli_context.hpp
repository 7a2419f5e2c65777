#pragma once
// Options every `rig` command shares, and output helpers (human tables or JSON).
#include <nlohmann/json_fwd.hpp>

#include <string>
#include <utility>
#include <vector>

#include "api_client.hpp"

namespace rig::cli {

struct CliContext {
  std::string api_url = "http://127.0.0.1:8080";
  std::string token_file;
  std::string archive_path = "/var/lib/rigd/archive.sqlite";
  std::string format = "table";  // table or json
  bool json() const { return format == "json"; }
  ApiClient client() const;
};

using Rows = std::vector<std::vector<std::string>>;
void print_table(const std::vector<std::string>& header, const Rows& rows);
void print_pairs(const std::vector<std::pair<std::string, std::string>>& pairs);
std::string fixed(double value, int decimals);
// Parses a reply body as JSON; throws naming the endpoint if it is not.
nlohmann::json parse_reply(const HttpReply& reply, const std::string& what);

}  // namespace rig::cli
