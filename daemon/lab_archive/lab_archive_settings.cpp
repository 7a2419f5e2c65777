#include "lab_archive_settings.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <fstream>

#include "pg_connection.hpp"

namespace rig::lab_archive {
namespace {

std::string read_password(const std::string& path) {
  struct stat info {};
  if (stat(path.c_str(), &info) != 0)
    throw LabArchiveError(path + ": lab_archive.password_file cannot be read");
  if ((info.st_mode & 077) != 0) {
    throw LabArchiveError(path + ": lab_archive.password_file may be read by others (mode " +
                          std::to_string((info.st_mode >> 6) & 7) +
                          std::to_string((info.st_mode >> 3) & 7) +
                          std::to_string(info.st_mode & 7) + "); chmod 600 it");
  }
  if (info.st_uid != geteuid())
    throw LabArchiveError(path + ": lab_archive.password_file is not owned by rigd's user");
  std::ifstream file(path);
  std::string password;
  if (!file || !std::getline(file, password))
    throw LabArchiveError(path + ": lab_archive.password_file is empty");
  while (!password.empty() && (password.back() == '\r' || password.back() == ' '))
    password.pop_back();
  return password;
}

}  // namespace

std::string default_rig_id() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return "rig";
  return name;
}

ConnectionParams connection_params(const LabArchiveSettings& settings) {
  ConnectionParams params{
      {"dbname", settings.conninfo}, {"sslmode", settings.sslmode}, {"connect_timeout", "5"},
      {"keepalives", "1"},           {"keepalives_idle", "5"},      {"keepalives_interval", "2"},
      {"keepalives_count", "3"},     {"tcp_user_timeout", "10000"}, {"application_name", "rigd"}};
  if (!settings.password_file.empty())
    params.emplace_back("password", read_password(settings.password_file));
  return params;
}

}  // namespace rig::lab_archive
