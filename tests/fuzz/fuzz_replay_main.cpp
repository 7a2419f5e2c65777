// The fuzz harnesses without libFuzzer (gcc trees, ASan + UBSan): each harness is fed its seed
// corpus, then a fixed number of inputs mutated from it (byte flips, inserts, erases, repeats,
// truncations, splices of two seeds) by a generator seeded with the harness's name, so a run
// is repeatable and a failure names the input it wrote. Coverage-guided fuzzing stays with
// `./rig fuzz` (clang, docs/fuzzing.md); this keeps every harness and its checks alive in
// every `./rig test` at a fraction of a fourth build tree's cost.
//
//   fuzz_replay TARGET CORPUS_DIR [MUTATIONS] [MAX_LEN]
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <random>
#include <string>
#include <vector>

// Each harness's LLVMFuzzerTestOneInput, renamed at compile time (tests/fuzz/CMakeLists.txt).
#define RIG_FUZZ_ENTRY(name) \
  extern "C" int rig_fuzz_##name(const std::uint8_t* data, std::size_t size);
RIG_FUZZ_ENTRY(run_csv)
RIG_FUZZ_ENTRY(config)
RIG_FUZZ_ENTRY(api_request)
RIG_FUZZ_ENTRY(modbus_response)
RIG_FUZZ_ENTRY(usb_response)
RIG_FUZZ_ENTRY(api_router)
RIG_FUZZ_ENTRY(auth_headers)
RIG_FUZZ_ENTRY(ws_frames)
RIG_FUZZ_ENTRY(model_file)
RIG_FUZZ_ENTRY(archive_rows)
RIG_FUZZ_ENTRY(lab_archive_rows)
#undef RIG_FUZZ_ENTRY

namespace {

using Bytes = std::vector<std::uint8_t>;
using Entry = int (*)(const std::uint8_t*, std::size_t);

const std::map<std::string, Entry>& entries() {
  static const std::map<std::string, Entry> table = {
      {"run_csv", rig_fuzz_run_csv},
      {"config", rig_fuzz_config},
      {"api_request", rig_fuzz_api_request},
      {"modbus_response", rig_fuzz_modbus_response},
      {"usb_response", rig_fuzz_usb_response},
      {"api_router", rig_fuzz_api_router},
      {"auth_headers", rig_fuzz_auth_headers},
      {"ws_frames", rig_fuzz_ws_frames},
      {"model_file", rig_fuzz_model_file},
      {"archive_rows", rig_fuzz_archive_rows},
      {"lab_archive_rows", rig_fuzz_lab_archive_rows}};
  return table;
}

Bytes read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// One edit of `input` (never longer than max_len) [bytes].
void mutate_once(Bytes& input, const Bytes& other, std::size_t max_len, std::mt19937_64& rng) {
  auto pick = [&](std::size_t n) {
    return n == 0 ? std::size_t{0} : static_cast<std::size_t>(rng() % n);
  };
  static constexpr char kSpecials[] = "\0\n\r\",;=[]{}:/%\\\xff\x7f 0-9eE.";
  switch (rng() % 7) {
    case 0:  // flip one bit
      if (!input.empty()) input[pick(input.size())] ^= static_cast<std::uint8_t>(1U << (rng() % 8));
      break;
    case 1:  // insert a byte a parser cares about
      if (input.size() < max_len)
        input.insert(input.begin() + static_cast<std::ptrdiff_t>(pick(input.size() + 1)),
                     static_cast<std::uint8_t>(kSpecials[pick(sizeof kSpecials - 1)]));
      break;
    case 2: {  // erase a range
      const std::size_t at = pick(input.size() + 1), n = std::min(input.size() - at, pick(16) + 1);
      input.erase(input.begin() + static_cast<std::ptrdiff_t>(at),
                  input.begin() + static_cast<std::ptrdiff_t>(at + n));
      break;
    }
    case 3: {  // repeat a range (long lines, many rows)
      if (input.empty()) break;
      const std::size_t at = pick(input.size()), n = std::min(input.size() - at, pick(64) + 1);
      const Bytes piece(input.begin() + static_cast<std::ptrdiff_t>(at),
                        input.begin() + static_cast<std::ptrdiff_t>(at + n));
      for (std::size_t r = pick(8) + 1; r > 0 && input.size() + piece.size() <= max_len; --r)
        input.insert(input.begin() + static_cast<std::ptrdiff_t>(at), piece.begin(), piece.end());
      break;
    }
    case 4:  // truncate
      input.resize(pick(input.size() + 1));
      break;
    case 5: {  // splice the tail of another seed
      const std::size_t from = pick(other.size() + 1);
      input.resize(pick(input.size() + 1));
      input.insert(input.end(), other.begin() + static_cast<std::ptrdiff_t>(from), other.end());
      if (input.size() > max_len) input.resize(max_len);
      break;
    }
    default:  // overwrite a byte with any value
      if (!input.empty()) input[pick(input.size())] = static_cast<std::uint8_t>(rng());
      break;
  }
}

// Written before each call so a crash (ASan aborts the process) leaves the input behind.
void keep_input(const std::string& target, const Bytes& input) {
  std::ofstream out("fuzz-replay-last-" + target, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(input.data()),
            static_cast<std::streamsize>(input.size()));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: fuzz_replay TARGET CORPUS_DIR [MUTATIONS] [MAX_LEN]\n");
    return 2;
  }
  const std::string target = argv[1];
  const auto entry = entries().find(target);
  if (entry == entries().end()) {
    std::fprintf(stderr, "fuzz_replay: no harness '%s'\n", target.c_str());
    return 2;
  }
  const long mutations = argc > 3 ? std::strtol(argv[3], nullptr, 10) : 500;
  const auto max_len =
      static_cast<std::size_t>(argc > 4 ? std::strtol(argv[4], nullptr, 10) : 4096);
  std::vector<Bytes> seeds;
  for (const auto& file : std::filesystem::directory_iterator(argv[2]))
    if (file.is_regular_file()) seeds.push_back(read_file(file.path()));
  if (seeds.empty()) {
    std::fprintf(stderr, "fuzz_replay: no seed in %s\n", argv[2]);
    return 2;
  }
  for (const Bytes& seed : seeds) {
    keep_input(target, seed);
    entry->second(seed.data(), seed.size());
  }
  std::mt19937_64 rng(std::hash<std::string>{}(target));
  for (long i = 0; i < mutations; ++i) {
    Bytes input = seeds[rng() % seeds.size()];
    const Bytes& other = seeds[rng() % seeds.size()];
    for (std::uint64_t edits = rng() % 8 + 1; edits > 0; --edits)
      mutate_once(input, other, max_len, rng);
    keep_input(target, input);
    entry->second(input.data(), input.size());
  }
  std::printf("fuzz_replay %s: %zu seeds and %ld mutated inputs, no finding\n", target.c_str(),
              seeds.size(), mutations);
  return 0;
}
