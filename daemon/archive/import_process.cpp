#include "import_process.hpp"

#include <unistd.h>

#include <fstream>
#include <sstream>

namespace rig::archive {
namespace {

std::string boot_id() {
  std::ifstream in("/proc/sys/kernel/random/boot_id");
  std::string id;
  in >> id;
  return id.empty() ? "unknown-boot" : id;
}

// Field 22 of /proc/PID/stat (after the parenthesised name, which may hold spaces); "" if
// the process does not exist.
std::string start_ticks(const std::string& pid) {
  std::ifstream in("/proc/" + pid + "/stat");
  std::string stat;
  std::getline(in, stat);
  const std::size_t name_end = stat.rfind(')');
  if (name_end == std::string::npos) return "";
  std::istringstream fields(stat.substr(name_end + 2));
  std::string field;
  for (int i = 3; i <= 22 && fields >> field; ++i) {
    if (i == 22) return field;
  }
  return "";
}

}  // namespace

std::string current_import_process() {
  const std::string pid = std::to_string(getpid());
  return boot_id() + " " + pid + " " + start_ticks(pid);
}

bool import_process_alive(const std::string& identity) {
  std::istringstream in(identity);
  std::string boot, pid, ticks;
  if (!(in >> boot >> pid >> ticks) || pid.find_first_not_of("0123456789") != std::string::npos)
    return false;
  return boot == boot_id() && start_ticks(pid) == ticks;
}

}  // namespace rig::archive
