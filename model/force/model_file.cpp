// Model files (TOML): reading with errors that name file, line and key; writing.
#include <toml++/toml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "force_model.hpp"

namespace rig::model {
namespace {

// A model of an eye: depths beyond 100 mm (an eye is 24 mm across) or a table of more than
// 1,000 IOP rows are typing errors, and lint would scan them for minutes.
constexpr double kMaxDepth_mm = 100.0;
constexpr std::size_t kMaxTableRows = 1000;

class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void fail(const toml::node* node, const std::string& key,
                         const std::string& what) const {
    const auto line = node != nullptr ? node->source().begin.line : 0U;
    throw ModelFileError(path_ + (line > 0 ? ":" + std::to_string(line) : "") + ": key '" + key +
                         "': " + what);
  }

  void only(const toml::table& table, const std::string& section,
            const std::set<std::string>& allowed) const {
    for (auto&& [name, node] : table) {
      if (allowed.count(std::string(name.str())) == 0U)
        fail(&node, (section.empty() ? "" : section + ".") + std::string(name.str()),
             "unknown key");
    }
  }

  double number(const toml::table& table, const std::string& section, const std::string& key,
                double fallback) const {
    const toml::node* node = table.get(key);
    if (node == nullptr) return fallback;
    if (!node->is_number()) fail(node, section + "." + key, "expected a number");
    const double value = *node->value<double>();
    if (!std::isfinite(value)) fail(node, section + "." + key, "not a finite number");
    return value;
  }

  std::vector<double> numbers(const toml::table& table, const std::string& section,
                              const std::string& key) const {
    const toml::node* node = table.get(key);
    if (node == nullptr || !node->is_array())
      fail(node, section + "." + key, "expected an array of numbers");
    std::vector<double> out;
    for (const auto& item : *node->as_array()) {
      if (!item.is_number()) fail(&item, section + "." + key, "expected an array of numbers");
      out.push_back(*item.value<double>());
      if (!std::isfinite(out.back())) fail(&item, section + "." + key, "not a finite number");
    }
    return out;
  }

  std::map<std::string, double> number_table(const toml::node& node,
                                             const std::string& section) const {
    if (!node.is_table()) fail(&node, section, "expected a table of numbers");
    std::map<std::string, double> out;
    for (auto&& [name, value] : *node.as_table()) {
      const std::string key(name.str());
      if (!value.is_number()) fail(&value, section + "." + key, "expected a number");
      out[key] = *value.value<double>();
    }
    return out;
  }

  std::string text(const toml::table& table, const std::string& section, const std::string& key,
                   const std::string& fallback) const {
    const toml::node* node = table.get(key);
    if (node == nullptr) return fallback;
    if (!node->is_string()) fail(node, section + "." + key, "expected a string");
    return *node->value<std::string>();
  }

  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

void read_table(const Reader& r, const toml::table& t, ForceModel& m) {
  r.only(t, "table", {"iop_mmHg", "x_pi_mm", "x_pf_mm"});
  m.table.iop_mmHg = r.numbers(t, "table", "iop_mmHg");
  m.table.x_pi_mm = r.numbers(t, "table", "x_pi_mm");
  m.table.x_pf_mm = r.numbers(t, "table", "x_pf_mm");
  const std::size_t n = m.table.iop_mmHg.size();
  if (n == 0 || m.table.x_pi_mm.size() != n || m.table.x_pf_mm.size() != n) {
    r.fail(t.get("iop_mmHg"), "table",
           "iop_mmHg, x_pi_mm and x_pf_mm need the same, non-zero length");
  }
  if (n > kMaxTableRows)
    r.fail(t.get("iop_mmHg"), "table.iop_mmHg",
           "more than " + std::to_string(kMaxTableRows) + " rows");
  for (std::size_t i = 1; i < n; ++i) {
    if (m.table.iop_mmHg[i] <= m.table.iop_mmHg[i - 1])
      r.fail(t.get("iop_mmHg"), "table.iop_mmHg", "must increase");
  }
  for (const auto& [key, depths] :
       {std::pair{"x_pi_mm", &m.table.x_pi_mm}, std::pair{"x_pf_mm", &m.table.x_pf_mm}}) {
    for (const double x : *depths) {
      if (x < 0.0 || x > kMaxDepth_mm)
        r.fail(t.get(key), std::string("table.") + key, "a depth outside 0..100 mm");
    }
  }
}

void read_parameters(const Reader& r, const toml::table& t, ContinuousParams& p) {
  r.only(t, "parameters",
         {"a", "x1", "b", "d", "e", "f", "g", "g0", "x_c", "w_drop", "w_release", "x_pi_shift",
          "x_pf_shift"});
  const std::string s = "parameters";
  p.a = r.number(t, s, "a", p.a);
  p.x1 = r.number(t, s, "x1", p.x1);
  p.b = r.number(t, s, "b", p.b);
  p.d = r.number(t, s, "d", p.d);
  p.e = r.number(t, s, "e", p.e);
  p.f = r.number(t, s, "f", p.f);
  p.g = r.number(t, s, "g", p.g);
  p.g0 = r.number(t, s, "g0", p.g0);
  p.x_c = r.number(t, s, "x_c", p.x_c);
  p.w_drop = r.number(t, s, "w_drop", p.w_drop);
  p.w_release = r.number(t, s, "w_release", p.w_release);
  p.x_pi_shift = r.number(t, s, "x_pi_shift", 0.0);
  p.x_pf_shift = r.number(t, s, "x_pf_shift", 0.0);
  for (const auto& [key, shift] :
       {std::pair{"x_pi_shift", p.x_pi_shift}, std::pair{"x_pf_shift", p.x_pf_shift}}) {
    if (std::abs(shift) > kMaxDepth_mm)
      r.fail(t.get(key), std::string("parameters.") + key, "a shift beyond +-100 mm");
  }
  if (p.w_drop <= 0.0) r.fail(t.get("w_drop"), "parameters.w_drop", "must be > 0");
}

void read_printed(const Reader& r, const toml::table& t, PrintedParams& p) {
  r.only(t, "printed", {"names", "values", "x_toe_end_mm", "x_cut_end_mm", "x_end_mm"});
  const toml::array* names = t.get_as<toml::array>("names");
  if (names == nullptr) r.fail(t.get("names"), "printed.names", "expected an array of strings");
  p.names.clear();
  for (const auto& n : *names) {
    if (!n.is_string()) r.fail(&n, "printed.names", "expected an array of strings");
    p.names.push_back(*n.value<std::string>());
  }
  p.values = r.numbers(t, "printed", "values");
  p.x_toe_end_mm = r.number(t, "printed", "x_toe_end_mm", p.x_toe_end_mm);
  p.x_cut_end_mm = r.number(t, "printed", "x_cut_end_mm", p.x_cut_end_mm);
  p.x_end_mm = r.number(t, "printed", "x_end_mm", p.x_end_mm);
}

std::vector<UserTerm> read_terms(const Reader& r, const toml::node* terms) {
  std::vector<UserTerm> out;
  if (terms == nullptr) return out;
  if (!terms->is_table()) r.fail(terms, "terms", "expected tables [terms.NAME]");
  for (auto&& [name, node] : *terms->as_table()) {
    const std::string section = "terms." + std::string(name.str());
    if (!node.is_table()) r.fail(&node, section, "expected a table");
    const toml::table& t = *node.as_table();
    r.only(t, section, {"expression", "phase", "params"});
    UserTerm term{std::string(name.str()),
                  r.text(t, section, "expression", ""),
                  r.text(t, section, "phase", "insertion"),
                  {}};
    if (term.expression.empty()) r.fail(&node, section + ".expression", "missing");
    if (const toml::node* params = t.get("params"))
      term.params = r.number_table(*params, section + ".params");
    out.push_back(std::move(term));
  }
  return out;
}

void read_extras(const Reader& r, const toml::table& root, ForceModel& m) {
  if (const toml::table* effects = root.get_as<toml::table>("effects")) {
    for (auto&& [name, node] : *effects) {
      m.effects.push_back(
          {std::string(name.str()), r.number_table(node, "effects." + std::string(name.str()))});
    }
  }
  m.user_terms = read_terms(r, root.get("terms"));
}

toml::table terms_table(const std::vector<UserTerm>& user_terms) {
  toml::table terms;
  for (const auto& u : user_terms) {
    toml::table p;
    for (const auto& [k, v] : u.params) p.insert(k, v);
    terms.insert(u.name,
                 toml::table{{"expression", u.expression}, {"phase", u.phase}, {"params", p}});
  }
  return terms;
}

// A model file is a small TOML file. A device (/dev/zero), a FIFO or a directory named by
// a client of POST /api/model would block or exhaust memory in the parser, so it is refused
// before any byte is read.
void require_small_regular_file(const std::string& path) {
  constexpr std::uintmax_t kMaxModelFileBytes = 4U << 20U;  // [bytes]; ours are ~2 kB
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) throw ModelFileError(path + ": no such model file");
  if (!std::filesystem::is_regular_file(status))
    throw ModelFileError(path + ": not a regular file (a model file is a TOML file)");
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec || bytes > kMaxModelFileBytes)
    throw ModelFileError(path + ": " + std::to_string(bytes) +
                         " bytes, more than a model file's limit of 4 MiB");
}

toml::table parse(const std::string& path) {
  require_small_regular_file(path);
  try {
    return toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    const auto line = e.source().begin.line;  // 0: the file itself (missing, unreadable)
    throw ModelFileError(path + (line > 0 ? ":" + std::to_string(line) : "") + ": " +
                         std::string(e.description()));
  }
}

void write(const std::string& path, const toml::table& root) {
  std::ofstream out(path);
  if (!out) throw ModelFileError(path + ": cannot write the model file");
  out << "# Written by rigd's model lab.\n" << root << "\n";
  if (!out) throw ModelFileError(path + ": write failed");
}

}  // namespace

ForceModel ForceModel::load(const std::string& path) {
  Reader r(path);
  const toml::table root = parse(path);
  r.only(root, "", {"model", "parameters", "printed", "table", "effects", "terms"});
  ForceModel m;
  m.path = path;
  const toml::table* head = root.get_as<toml::table>("model");
  if (head == nullptr) r.fail(nullptr, "model", "missing [model] section");
  r.only(*head, "model", {"name", "form", "velocity_mm_s", "description"});
  m.name = r.text(*head, "model", "name", path);
  const std::string form = r.text(*head, "model", "form", "eq1-continuous");
  if (form != "eq1-continuous" && form != "eq1-printed")
    r.fail(head->get("form"), "model.form", "expected eq1-continuous or eq1-printed");
  m.form = form == "eq1-printed" ? ModelForm::kPrinted : ModelForm::kContinuous;
  m.reference_velocity_mm_s = r.number(*head, "model", "velocity_mm_s", 2.0);
  if (const toml::table* t = root.get_as<toml::table>("table")) read_table(r, *t, m);
  if (m.form == ModelForm::kPrinted) {
    const toml::table* t = root.get_as<toml::table>("printed");
    if (t == nullptr) r.fail(nullptr, "printed", "missing [printed] section for form eq1-printed");
    read_printed(r, *t, m.printed);
  } else if (const toml::table* t = root.get_as<toml::table>("parameters")) {
    read_parameters(r, *t, m.params);
  }
  read_extras(r, root, m);
  return m;
}

void ForceModel::save(const std::string& out_path) const {
  toml::table root;
  root.insert("model",
              toml::table{{"name", name},
                          {"form", form == ModelForm::kPrinted ? "eq1-printed" : "eq1-continuous"},
                          {"velocity_mm_s", reference_velocity_mm_s}});
  auto array = [](const std::vector<double>& v) {
    toml::array a;
    for (const double x : v) a.push_back(x);
    return a;
  };
  if (form == ModelForm::kContinuous) {
    const ContinuousParams& p = params;
    root.insert("parameters", toml::table{{"a", p.a},
                                          {"x1", p.x1},
                                          {"b", p.b},
                                          {"d", p.d},
                                          {"e", p.e},
                                          {"f", p.f},
                                          {"g", p.g},
                                          {"g0", p.g0},
                                          {"x_c", p.x_c},
                                          {"w_drop", p.w_drop},
                                          {"w_release", p.w_release},
                                          {"x_pi_shift", p.x_pi_shift},
                                          {"x_pf_shift", p.x_pf_shift}});
  } else {
    toml::array names;
    for (const auto& n : printed.names) names.push_back(n);
    root.insert("printed", toml::table{{"names", names},
                                       {"values", array(printed.values)},
                                       {"x_toe_end_mm", printed.x_toe_end_mm},
                                       {"x_cut_end_mm", printed.x_cut_end_mm},
                                       {"x_end_mm", printed.x_end_mm}});
  }
  root.insert("table", toml::table{{"iop_mmHg", array(table.iop_mmHg)},
                                   {"x_pi_mm", array(table.x_pi_mm)},
                                   {"x_pf_mm", array(table.x_pf_mm)}});
  toml::table effect_table;
  for (const auto& e : effects) {
    toml::table t;
    for (const auto& [k, v] : e.params) t.insert(k, v);
    effect_table.insert(e.name, t);
  }
  if (!effects.empty()) root.insert("effects", effect_table);
  if (!user_terms.empty()) root.insert("terms", terms_table(user_terms));
  write(out_path, root);
}

std::vector<UserTerm> load_user_terms(const std::string& path) {
  Reader r(path);
  const toml::table root = parse(path);
  r.only(root, "", {"terms"});
  std::vector<UserTerm> terms = read_terms(r, root.get("terms"));
  if (terms.empty()) r.fail(nullptr, "terms", "no [terms.NAME] table in the term file");
  return terms;
}

void save_user_terms(const std::string& path, const std::vector<UserTerm>& terms) {
  write(path, toml::table{{"terms", terms_table(terms)}});
}

}  // namespace rig::model
