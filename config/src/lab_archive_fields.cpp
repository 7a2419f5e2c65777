// [lab_archive]: declared keys and the checks across them.
#include <functional>

#include "config_schema.hpp"
#include "rig/config/config_error.hpp"

namespace rig::config {
namespace {

using Type = ConfigField::Type;

ConfigField string_field(std::string key, std::vector<std::string> choices, std::string doc,
                         std::string LabArchiveSection::*member, bool is_path = false) {
  ConfigField field{std::move(key),
                    Type::kString,
                    0,
                    0,
                    std::move(choices),
                    std::move(doc),
                    [member](RigdConfig& c, const ConfigValue& v) {
                      c.lab_archive.*member = std::get<std::string>(v);
                    }};
  field.is_path = is_path;
  return field;
}

ConfigField int_field(std::string key, double min, double max, std::string doc,
                      int LabArchiveSection::*member) {
  return {std::move(key),
          Type::kInteger,
          min,
          max,
          {},
          std::move(doc),
          [member](RigdConfig& c, const ConfigValue& v) {
            c.lab_archive.*member = static_cast<int>(std::get<std::int64_t>(v));
          }};
}

// password=... in a keyword string, or user:password@ in a URI: the config file is readable
// by technicians, the password file only by rigd.
bool lab_conninfo_holds_password(const std::string& conninfo) {
  if (conninfo.find("password") != std::string::npos) return true;
  const auto scheme = conninfo.find("://");
  const auto at = conninfo.find('@');
  if (scheme == std::string::npos || at == std::string::npos || at < scheme) return false;
  return conninfo.substr(scheme + 3, at - scheme - 3).find(':') != std::string::npos;
}

}  // namespace

void add_lab_archive_fields(std::vector<ConfigField>& f) {
  f.push_back(
      {"lab_archive.enabled",
       Type::kBoolean,
       0,
       0,
       {},
       "ship the archive to the lab's PostgreSQL (store and forward)",
       [](RigdConfig& c, const ConfigValue& v) { c.lab_archive.enabled = std::get<bool>(v); }});
  f.push_back(string_field("lab_archive.conninfo", {},
                           "libpq connection string or postgresql:// URI, without the password",
                           &LabArchiveSection::conninfo));
  f.push_back(string_field("lab_archive.password_file", {},
                           "file holding the password (mode 0600, owned by rigd's user)",
                           &LabArchiveSection::password_file, true));
  f.push_back(string_field("lab_archive.sslmode",
                           {"disable", "allow", "prefer", "require", "verify-ca", "verify-full"},
                           "TLS to the server (libpq sslmode)", &LabArchiveSection::sslmode));
  f.push_back(string_field("lab_archive.rig_id", {},
                           "this rig's name in the lab archive (default: host name)",
                           &LabArchiveSection::rig_id));
  f.push_back(int_field("lab_archive.interval_ms", 10, 60000,
                        "pause between passes when nothing waits [ms]",
                        &LabArchiveSection::interval_ms));
  f.push_back(int_field("lab_archive.batch_samples", 100, 10000000,
                        "most samples per pass [samples]", &LabArchiveSection::batch_samples));
  f.push_back(int_field("lab_archive.retry_max_ms", 100, 600000,
                        "longest wait between reconnection attempts [ms]",
                        &LabArchiveSection::retry_max_ms));
}

void check_lab_archive(const LabArchiveSection& lab,
                       const std::function<void(const std::string&)>& fail) {
  if (lab_conninfo_holds_password(lab.conninfo)) {
    fail(
        "key 'lab_archive.conninfo' must not hold a password: put it in "
        "'lab_archive.password_file' (mode 0600)");
  }
  if (lab.enabled && lab.conninfo.empty())
    fail("key 'lab_archive.conninfo' is required when 'lab_archive.enabled' = true");
}

}  // namespace rig::config
