// proto-gen: messages.json -> C++ structs with to_json / validating from_json.
// Usage: proto-gen messages.json out_dir   (writes rig/proto/messages.hpp and messages.cpp)
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

namespace {

using Json = nlohmann::ordered_json;

struct FieldType {
  std::string cpp;       // C++ type of the member
  bool message = false;  // nested message or array of them
};

FieldType cpp_type(const std::string& type, const std::set<std::string>& known,
                   const std::string& where) {
  if (type == "string") return {"std::string"};
  if (type == "number") return {"double"};
  if (type == "integer") return {"std::int64_t"};
  if (type == "boolean") return {"bool"};
  if (type == "map<string>") return {"std::map<std::string, std::string>"};
  if (type.rfind("array<", 0) == 0 && type.back() == '>') {
    const FieldType inner = cpp_type(type.substr(6, type.size() - 7), known, where);
    return {"std::vector<" + inner.cpp + ">", inner.message};
  }
  if (known.count(type) != 0U) return {type, true};
  throw std::runtime_error(where + ": unknown type '" + type + "' (declare messages before use)");
}

std::string quote(const std::string& text) {
  return Json(text).dump();
}

// JSON names that are C++ keywords get a trailing underscore as member names.
std::string member_name(const std::string& field) {
  static const std::set<std::string> kReserved = {"operator", "class",    "default",  "delete",
                                                  "new",      "this",     "template", "namespace",
                                                  "union",    "register", "switch"};
  return kReserved.count(field) != 0U ? field + "_" : field;
}

std::string limits(const Json& f) {
  std::ostringstream out;
  out << "detail::Limits{";
  auto opt = [&](const char* key) {
    return f.contains(key) ? f[key].dump() : std::string("std::nullopt");
  };
  out << opt("min") << ", " << opt("max") << ", " << opt("min_length") << ", " << opt("max_length")
      << ", " << opt("max_items") << ", "
      << (f.contains("pattern") ? quote(f["pattern"]) : "nullptr") << "}";
  return out.str();
}

void emit_message(const std::string& name, const Json& message, std::set<std::string>& known,
                  std::ostream& hpp, std::ostream& cpp) {
  const Json& fields = message.at("fields");
  hpp << "// " << message.value("doc", "") << "\nstruct " << name << " {\n";
  std::ostringstream reads;
  std::ostringstream writes;
  std::ostringstream names;
  for (const auto& [field, spec] : fields.items()) {
    const FieldType type = cpp_type(spec.at("type"), known, name + "." + field);
    const bool optional = spec.value("optional", false);
    const std::string member = optional ? "std::optional<" + type.cpp + ">" : type.cpp;
    const std::string init = (type.cpp == "double" || type.cpp == "std::int64_t")
                                 ? " = 0"
                                 : (type.cpp == "bool" ? " = false" : "");
    const std::string m = member_name(field);
    hpp << "  " << member << " " << m << (optional ? "" : init) << ";";
    if (spec.contains("doc")) hpp << "  // " << spec["doc"].get<std::string>();
    hpp << "\n";
    reads << "  detail::read_field(j, " << quote(field) << ", out." << m << ", " << limits(spec)
          << ");\n";
    if (optional) {
      writes << "  if (in." << m << ") j[" << quote(field) << "] = *in." << m << ";\n";
    } else {
      writes << "  j[" << quote(field) << "] = in." << m << ";\n";
    }
    names << (names.tellp() > 0 ? ", " : "") << quote(field);
  }
  hpp << "};\nvoid to_json(nlohmann::json& j, const " << name << "& in);\n"
      << "void from_json(const nlohmann::json& j, " << name << "& out);\n\n";
  cpp << "void to_json(nlohmann::json& j, const " << name
      << "& in) {\n  j = nlohmann::json::object();\n"
      << writes.str() << "}\n\n";
  cpp << "void from_json(const nlohmann::json& j, " << name << "& out) {\n"
      << "  detail::require_object(j, " << quote(name) << ");\n"
      << "  detail::reject_unknown(j, {" << names.str() << "});\n"
      << reads.str() << "}\n\n";
  known.insert(name);
}

std::string raw_string(const std::string& text) {
  std::ostringstream out;  // split into chunks: compilers cap string literal length
  out << "std::string() ";
  for (std::size_t i = 0; i < text.size(); i += 4000) {
    out << "+ std::string(R\"rigproto(" << text.substr(i, 4000) << ")rigproto\")\n    ";
  }
  return out.str();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: proto-gen messages.json out_dir\n";
    return 2;
  }
  try {
    std::ifstream in(argv[1]);
    if (!in) throw std::runtime_error(std::string(argv[1]) + ": cannot open");
    std::stringstream text;
    text << in.rdbuf();
    const Json schema = Json::parse(text.str());
    std::ostringstream hpp;
    std::ostringstream cpp;
    hpp << "#pragma once\n// Generated by proto-gen from proto/messages.json. Do not edit.\n"
        << "#include <nlohmann/json_fwd.hpp>\n\n#include <cstdint>\n#include <map>\n#include "
           "<optional>\n"
        << "#include <stdexcept>\n#include <string>\n#include <vector>\n\nnamespace rig::proto "
           "{\n\n"
        << "// A message that does not match its schema; field() names the offending field.\n"
        << "class ProtoError : public std::runtime_error {\n public:\n"
        << "  ProtoError(std::string field, std::string reason);\n"
        << "  const std::string& field() const { return field_; }\n"
        << "  const std::string& reason() const { return reason_; }\n\n private:\n"
        << "  std::string field_;\n  std::string reason_;\n};\n\n"
        << "inline constexpr int kSchemaVersion = " << schema.at("version").get<int>() << ";\n"
        << "const std::string& messages_schema_json();\n\n";
    cpp << "// Generated by proto-gen from proto/messages.json. Do not edit.\n"
        << "#include \"rig/proto/messages.hpp\"\n\n#include <nlohmann/json.hpp>\n\n#include "
           "\"proto_runtime.hpp\"\n\n"
        << "namespace rig::proto {\n\nconst std::string& messages_schema_json() {\n  static const "
           "std::string kText = "
        << raw_string(text.str()) << ";\n  return kText;\n}\n\n";
    std::set<std::string> known;
    for (const auto& [name, message] : schema.at("messages").items())
      emit_message(name, message, known, hpp, cpp);
    hpp << "}  // namespace rig::proto\n";
    cpp << "}  // namespace rig::proto\n";
    const std::filesystem::path out_dir(argv[2]);
    std::filesystem::create_directories(out_dir / "rig" / "proto");
    std::ofstream(out_dir / "rig" / "proto" / "messages.hpp") << hpp.str();
    std::ofstream(out_dir / "messages.cpp") << cpp.str();
  } catch (const std::exception& e) {
    std::cerr << "proto-gen: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
