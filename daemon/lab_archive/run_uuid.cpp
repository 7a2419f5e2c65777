#include "run_uuid.hpp"

#include <cstdio>

namespace rig::lab_archive {
namespace {

std::uint64_t fnv1a(const std::string& text, std::uint64_t hash) {
  for (const unsigned char c : text) {
    hash ^= c;
    hash *= 1099511628211ULL;
  }
  return hash;
}

}  // namespace

std::string lab_run_uuid(const std::string& rig_id, std::int64_t local_run_id,
                         const std::string& created_at) {
  const std::string key = rig_id + '\x1f' + std::to_string(local_run_id) + '\x1f' + created_at;
  std::uint64_t high = fnv1a(key, 14695981039346656037ULL);
  std::uint64_t low = fnv1a(key + "\x1e", high ^ 0x9e3779b97f4a7c15ULL);
  high = (high & ~0xF000ULL) | 0x8000ULL;          // version 8 (custom, RFC 9562)
  low = (low & ~(0x3ULL << 62)) | (0x2ULL << 62);  // RFC variant
  char text[40];
  std::snprintf(text, sizeof text, "%08x-%04x-%04x-%04x-%012llx", static_cast<unsigned>(high >> 32),
                static_cast<unsigned>((high >> 16) & 0xFFFF), static_cast<unsigned>(high & 0xFFFF),
                static_cast<unsigned>(low >> 48),
                static_cast<unsigned long long>(low & 0xFFFFFFFFFFFFULL));
  return text;
}

}  // namespace rig::lab_archive
