#pragma once
// The command lines a document shows: every line of its code blocks (indented or fenced) that
// starts with a program of ours or one the docs tell people to use, joined over trailing
// backslashes, without trailing `# comments`; and inline code that starts with `./rig `.
#include <fstream>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace rig::testing {

struct DocumentedCommand {
  std::string file;
  int line = 0;
  std::string text;
};

// `also`: more programs, e.g. "socat|mkdir" where a block prepares what the next lines use.
inline bool is_command_of_ours(const std::string& text, const std::string& also = "") {
  const std::regex program("^(\\./rig|rig|rigd|rig-sim|mbpoll" + (also.empty() ? "" : "|" + also) +
                           ")( |$)");
  return std::regex_search(text, program);
}

inline std::string without_comment(const std::string& text) {
  static const std::regex kComment(R"(\s+#\s.*$)");
  return std::regex_replace(text, kComment, "");
}

inline std::vector<DocumentedCommand> documented_commands(const std::string& path,
                                                          const std::string& name,
                                                          const std::string& also = "") {
  std::ifstream in(path);
  std::vector<DocumentedCommand> found;
  std::set<std::string> seen;
  auto add = [&](int line, std::string text) {
    while (!text.empty() && text.back() == ' ') text.pop_back();
    if (is_command_of_ours(text, also) && seen.insert(text).second)
      found.push_back({name, line, text});
  };
  static const std::regex kInline(R"(`(\./rig [^`<]*)`)");
  std::string line, pending;
  int number = 0, pending_line = 0;
  bool fenced = false, previous_blank = true, in_indented = false;
  while (std::getline(in, line)) {
    ++number;
    if (line.rfind("```", 0) == 0) {
      fenced = !fenced;
      continue;
    }
    in_indented = !fenced && line.rfind("    ", 0) == 0 && (previous_blank || in_indented);
    previous_blank = line.find_first_not_of(' ') == std::string::npos;
    if (fenced || in_indented) {
      std::string text = line.substr(
          line.find_first_not_of(' ') == std::string::npos ? 0 : line.find_first_not_of(' '));
      if (pending.empty()) pending_line = number;
      text = without_comment(text);
      if (!text.empty() && text.back() == '\\') {
        pending += text.substr(0, text.size() - 1);
        continue;
      }
      add(pending_line, pending + text);
      pending.clear();
      continue;
    }
    for (std::sregex_iterator it(line.begin(), line.end(), kInline), end; it != end; ++it)
      add(number, (*it)[1]);
  }
  return found;
}

}  // namespace rig::testing
