#include "io/case_loader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>
#include <toml.hpp>
#include <type_traits>
#include <utility>

#include "io/case_loading.hpp"
#include "io/case_schema.hpp"
#include "io/list_schema.hpp"
#include "io/stl_mesh.hpp"
#include "poisson/linear_solver.hpp"

namespace isph {

namespace {

using namespace case_loading;

using Vec3 = std::array<double, 3>;
using Choices = std::vector<std::string>;

enum class Need { optional, required };

// ---------------------------------------------------------------------------------------------
// Reading: every problem is recorded in the Context, and reading goes on.
// ---------------------------------------------------------------------------------------------

class Table;

bool convert(const toml::value& v, const std::string& path, Context& ctx, bool& out);
bool convert(const toml::value& v, const std::string& path, Context& ctx, std::int64_t& out);
bool convert(const toml::value& v, const std::string& path, Context& ctx, double& out);
bool convert(const toml::value& v, const std::string& path, Context& ctx, std::string& out);
bool convert(const toml::value& v, const std::string& path, Context& ctx, Vec3& out);
template <class T>
bool convert(const toml::value& v, const std::string& path, Context& ctx, std::vector<T>& out);
template <class T>
requires requires(Table& t, T& spec) { read_fields(t, spec); }
bool convert(const toml::value& v, const std::string& path, Context& ctx, T& out);

// One TOML table being read. Keys are taken by name; when the reader goes away, every key that
// nobody asked for is reported as unknown.
class Table {
 public:
  Table(const toml::table& table, std::string path, Context& ctx) : table_(table), path_(std::move(path)), ctx_(ctx) {}
  Table(const Table&) = delete;
  Table& operator=(const Table&) = delete;
  ~Table() { report_unknown(); }

  Context& ctx() { return ctx_; }
  bool has(const std::string& key) const { return table_.count(key) != 0; }
  std::string path(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  void problem(const std::string& key, const std::string& reason) { ctx_.problem(path(key), reason); }
  void ignore(const std::string& key) { used_.insert(key); }
  // After an invalid `type` the other keys cannot be judged; they are not reported.
  void ignore_rest() {
    for (const auto& entry : table_) used_.insert(entry.first);
  }

  // Converts `key` into `out` if present (`out` keeps its default otherwise); returns whether
  // `out` was set from the file.
  template <class T>
  bool read(const std::string& key, T& out, Need need = Need::optional) {
    used_.insert(key);
    const auto it = table_.find(key);
    if (it == table_.end()) {
      if (need == Need::required) problem(key, "missing required key");
      return false;
    }
    return convert(it->second, path(key), ctx_, out);
  }

 private:
  void report_unknown() {
    std::set<std::string> unknown;  // sorted, so that reports are reproducible
    for (const auto& entry : table_)
      if (!used_.count(entry.first)) unknown.insert(entry.first);
    for (const auto& key : unknown) problem(key, "unknown key");
  }

  const toml::table& table_;
  std::string path_;
  Context& ctx_;
  std::set<std::string> used_;
};

bool mismatch(const toml::value& v, const std::string& expected, const std::string& path, Context& ctx) {
  ctx.problem(path, "expected " + expected + ", got " + describe(v));
  return false;
}

bool convert(const toml::value& v, const std::string& path, Context& ctx, bool& out) {
  if (!v.is_boolean()) return mismatch(v, "a boolean", path, ctx);
  out = v.as_boolean();
  return true;
}

bool convert(const toml::value& v, const std::string& path, Context& ctx, std::int64_t& out) {
  if (!v.is_integer()) return mismatch(v, "an integer", path, ctx);
  out = v.as_integer();
  return true;
}

// Integers are accepted where floats are expected (dx = 1 means 1.0).
bool convert(const toml::value& v, const std::string& path, Context& ctx, double& out) {
  if (!v.is_floating() && !v.is_integer()) return mismatch(v, "a number", path, ctx);
  const double x = v.is_integer() ? static_cast<double>(v.as_integer()) : v.as_floating();
  if (!std::isfinite(x)) {
    ctx.problem(path, "must be finite (got " + shortest_number(x) + ")");
    return false;
  }
  out = x;
  return true;
}

bool convert(const toml::value& v, const std::string& path, Context& ctx, std::string& out) {
  if (!v.is_string()) return mismatch(v, "a string", path, ctx);
  out = v.as_string().str;
  return true;
}

// A point or vector: exactly `dimension` numbers; the unused components keep their defaults, so that a
// case reads back to the same case whether or not the file gives the key.
bool convert(const toml::value& v, const std::string& path, Context& ctx, Vec3& out) {
  const std::string expected = std::to_string(ctx.dimension) + " numbers";
  if (!v.is_array()) return mismatch(v, "an array of " + expected, path, ctx);
  const auto& items = v.as_array();
  if (items.size() != static_cast<std::size_t>(ctx.dimension)) {
    ctx.problem(path, "expected " + expected + " (dimension = " + std::to_string(ctx.dimension) + "), got " +
                          std::to_string(items.size()));
    return false;
  }
  Vec3 result = out;
  bool ok = true;
  for (std::size_t i = 0; i < items.size(); ++i) ok = convert(items[i], index_path(path, i), ctx, result[i]) && ok;
  if (ok) out = result;
  return ok;
}

// An array (of tables, usually). Every element is kept, valid or not, so that the indices used by
// the checks across lists match the file.
template <class T>
bool convert(const toml::value& v, const std::string& path, Context& ctx, std::vector<T>& out) {
  if (!v.is_array()) return mismatch(v, "an array", path, ctx);
  const auto& items = v.as_array();
  std::vector<T> result(items.size());
  bool ok = true;
  for (std::size_t i = 0; i < items.size(); ++i) ok = convert(items[i], index_path(path, i), ctx, result[i]) && ok;
  out = std::move(result);
  return ok;
}

// Every spec with a read_fields overload is read from a TOML table (or inline table).
template <class T>
requires requires(Table& t, T& spec) { read_fields(t, spec); }
bool convert(const toml::value& v, const std::string& path, Context& ctx, T& out) {
  if (!v.is_table()) return mismatch(v, "a table", path, ctx);
  Table table(v.as_table(), path, ctx);
  read_fields(table, out);
  return true;
}

// ---------------------------------------------------------------------------------------------
// Checked reads
// ---------------------------------------------------------------------------------------------

// A key that is not allowed here (given the values read before it): reported, and not read.
void reject(Table& t, const std::string& key, const std::string& reason) {
  if (!t.has(key)) return;
  t.ignore(key);
  t.problem(key, reason);
}

// ---------------------------------------------------------------------------------------------
// The lists' elements: read from their declared keys (list_schema.hpp), then each one's cross-key rules
// ---------------------------------------------------------------------------------------------

// An integer key: read as TOML's 64-bit integer, checked against its bounds and an int's range.
template <class Item>
bool read_value(Table& t, const SchemaKey<Item>& key, int& target, Need need) {
  std::int64_t value = target;
  if (!t.read(key.name, value, need)) return false;
  if (!key.bounds.admits(static_cast<double>(value))) {
    t.problem(key.name, "must be " + key.bounds.text(true) + " (got " + std::to_string(value) + ")");
    return false;
  }
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()) {
    t.problem(key.name, "must fit an int (got " + std::to_string(value) + ")");
    return false;
  }
  target = static_cast<int>(value);
  return true;
}

// A value key: read into a copy, checked (bounds, a direction's length), then stored. Returns whether the
// file gave a valid value.
template <class T, class Item>
bool read_value(Table& t, const SchemaKey<Item>& key, T& target, Need need) {
  T value = target;
  if (!t.read(key.name, value, need)) return false;
  if constexpr (std::is_same_v<T, double>) {
    if (!key.bounds.admits(value)) {
      t.problem(key.name, "must be " + key.bounds.text(false) + " (got " + shortest_number(value) + ")");
      return false;
    }
  }
  if constexpr (std::is_same_v<T, Vec3>) {
    if (key.direction) {
      const double norm = std::sqrt(value[0] * value[0] + value[1] * value[1] + value[2] * value[2]);
      if (norm == 0.0) {
        t.problem(key.name, "must not be the zero vector");
        return false;
      }
      // A unit vector stays as given: normalizing it again could change its last bits, and the resolved
      // case must load back to the same case.
      if (std::abs(norm - 1.0) > 4 * std::numeric_limits<double>::epsilon())
        for (auto& c : value) c /= norm;
    }
  }
  target = std::move(value);
  return true;
}

// A choice key: one of the names the dimension offers.
template <class Item>
bool read_name(Table& t, const SchemaKey<Item>& key, Item& item, Need need) {
  std::string name;
  if (!t.read(key.name, name, need)) return false;
  if (std::find(key.choices.begin(), key.choices.end(), name) == key.choices.end()) {
    t.problem(key.name, one_of(key.choices_in ? key.choices_in(t.ctx().dimension) : key.choices) + " (got " +
                            toml_string(name) + ")");
    return false;
  }
  key.set_name(item, name);
  return true;
}

// Reads one declared key of an element, in its order among the element's keys. A key not for this element
// (given the keys before it and the dimension) is reported if the file gives it; a bad value is reported
// and leaves the default. Adds the key to `read` when the file gave a valid value; returns false when a
// missing or bad discriminator (a type, a model) must stop the reading of the element's other keys.
template <class Item>
bool read_key(Table& t, Item& item, const SchemaKey<Item>& key, std::set<std::string>& read) {
  const int d = t.ctx().dimension;
  if (key.applies && !key.applies(item, d)) {
    reject(t, key.name, key.not_for(item, d));
    return true;
  }
  if (key.preset) key.preset(item, d);
  const Need need = key.required && key.required(item) ? Need::required : Need::optional;
  const Item before = item;
  bool ok = key.set_name ? read_name(t, key, item, need)
                         : std::visit([&](auto* field) { return read_value(t, key, *field, need); }, key.field(item));
  if (ok && key.check) {
    if (const std::string problem = key.check(item, d); !problem.empty()) {
      t.problem(key.name, problem);
      item = before;
      ok = false;
    }
  }
  if (ok) read.insert(key.name);
  return ok || !key.discriminator || (need != Need::required && !t.has(key.name));
}

// Reads an element's declared keys in their order; after a missing or bad discriminator the other keys
// are not judged. Returns the keys read, or nothing when a discriminator stopped the reading.
template <class Item>
std::optional<std::set<std::string>> read_item(Table& t, Item& item, const std::vector<SchemaKey<Item>>& keys) {
  std::set<std::string> read;
  for (const auto& key : keys) {
    if (!read_key(t, item, key, read)) {
      t.ignore_rest();
      return std::nullopt;
    }
  }
  return read;
}

// An stl shape's mesh is read here, relative to the case file's folder, and must be closed; the resolved
// configuration names the file by its absolute path.
void read_mesh(Table& t, Shape& s) {
  std::filesystem::path file(s.file);
  if (file.is_relative()) file = std::filesystem::path(t.ctx().file).parent_path() / file;
  s.file = std::filesystem::absolute(file).lexically_normal().string();
  try {
    s.mesh.mesh = StlMesh::load(s.file, s.scale, s.translate);
  } catch (const std::exception& e) {
    t.problem("file", e.what());
    return;
  }
  if (!s.mesh.mesh->closed()) {
    t.problem("file", toml_string(s.file) + " is not a closed surface (" + std::to_string(s.mesh.mesh->border_edges()) +
                          " edges border one triangle only); an stl shape must be watertight");
    s.mesh.mesh.reset();
  }
}

void read_fields(Table& t, Shape& s) {
  const auto read = read_item(t, s, shape_keys());
  if (read && s.type == ShapeType::stl && read->count("file")) read_mesh(t, s);
  if (!read || is_ball(s.type) || !read->count("min") || !read->count("max")) return;
  for (int k = 0; k < t.ctx().dimension; ++k) {
    if (s.min[k] < s.max[k]) continue;
    t.problem("max", "must be > min in every component (component " + std::to_string(k) + ": min " +
                         shortest_number(s.min[k]) + ", max " + shortest_number(s.max[k]) + ")");
    return;
  }
}

void read_fields(Table& t, InitialVelocitySpec& v) { read_item(t, v, initial_velocity_keys()); }
void read_fields(Table& t, MotionSpec& m) { read_item(t, m, motion_keys()); }
void read_fields(Table& t, LoadSpec& l) { read_item(t, l, load_keys()); }
void read_fields(Table& t, ProbeSpec& p) { read_item(t, p, probe_keys()); }
void read_fields(Table& t, OpenBoundarySpec& o) { read_item(t, o, open_boundary_keys()); }
void read_fields(Table& t, PeriodicSpec& p) { read_item(t, p, periodic_keys()); }

// Exactly one of youngs_modulus and bulk_modulus K; from K, E = 3K(1 - 2 nu). An unknown model leaves the
// material's bodies unjudged (check_material_model).
void read_fields(Table& t, MaterialSpec& m) {
  const auto read = read_item(t, m, material_keys());
  if (!read) {
    t.ctx().unknown_model.insert(m.name);
    return;
  }
  if (m.model == MaterialModel::newtonian) return;
  const bool has_e = t.has("youngs_modulus"), has_k = t.has("bulk_modulus");
  if (has_e == has_k)
    t.problem("youngs_modulus",
              has_e ? "give youngs_modulus or bulk_modulus, not both" : "missing required key (or give bulk_modulus)");
  else if (read->count("bulk_modulus"))
    m.youngs_modulus = 3.0 * m.bulk_modulus * (1.0 - 2.0 * m.poisson_ratio);
}

void read_fields(Table& t, BodySpec& b) {
  read_item(t, b, body_keys());
  if (t.has("dx") && t.has("refinement")) t.problem("dx", "give the body's spacing as dx or as refinement, not both");
}

// ---------------------------------------------------------------------------------------------
// The settings: read from the declared keys (case_schema.hpp), then each section's cross-key rules
// ---------------------------------------------------------------------------------------------

// The default surface thresholds on div r (case.hpp: FluidSpec).
double default_surface_threshold(int dimension) { return dimension == 2 ? 1.4 : 2.4; }
double default_surface_full(int dimension) { return dimension == 2 ? 1.6 : 2.6; }

void check_fluid(Table& t, CaseSpec& c) {
  FluidSpec& f = c.fluid;
  // Judged with the defaults in place of zeros, so that a threshold above the default full value is caught.
  const int d = t.ctx().dimension;
  const double threshold = f.surface_threshold > 0.0 ? f.surface_threshold : default_surface_threshold(d);
  const double full = f.surface_full > 0.0 ? f.surface_full : default_surface_full(d);
  if (!(full > threshold))
    t.problem("surface_full", "must be > surface_threshold (got " + shortest_number(full) +
                                  (f.surface_full > 0.0 ? "" : " (default)") + " <= " + shortest_number(threshold) +
                                  (f.surface_threshold > 0.0 ? "" : " (default)") + ")");
}

// The method and the preconditioner must be the backend's; the preconditioner's default follows the
// backend, and a case that names a backend gets no fallback unless it names one (case.hpp).
void check_ppe(Table& t, CaseSpec& c) {
  PpeSolverSpec& p = c.fluid.ppe;
  const auto names = [](const auto& options) {
    Choices n;
    for (const auto o : options) n.push_back(name_of(o));
    return n;
  };
  const std::string with = " is not available with backend = " + toml_string(name_of(p.backend)) + "; ";
  const auto& methods = solver_methods(p.backend);
  if (std::find(methods.begin(), methods.end(), p.method) == methods.end())
    t.problem("method", toml_string(name_of(p.method)) + with + one_of(names(methods)));
  const auto& preconditioners = solver_preconditioners(p.backend);
  if (!t.has("preconditioner"))
    p.preconditioner = preconditioners.front();
  else if (std::find(preconditioners.begin(), preconditioners.end(), p.preconditioner) == preconditioners.end())
    t.problem("preconditioner", toml_string(name_of(p.preconditioner)) + with + one_of(names(preconditioners)));
  if (t.has("backend") && !t.has("fallback")) p.fallback = FallbackSolver::none;
  if (name_of(p.fallback) == name_of(p.backend))
    t.problem("fallback", "must differ from backend (both " + toml_string(name_of(p.backend)) + "), or be \"none\"");
}

// Seed 002 §2.2: the acoustic Courant number defaults to 0.6 with dual-criteria stepping, 0.25 without.
void check_wcsph(Table& t, CaseSpec& c) {
  WcsphSpec& w = c.fluid.wcsph;
  if (!t.has("acoustic_courant")) w.acoustic_courant = w.time_stepping == WcsphTimeStepping::dual_criteria ? 0.6 : 0.25;
}

// A settings section being read: the target of a sub-table such as [fluid.ppe].
struct Section {
  CaseSpec* spec = nullptr;
  std::string name;
};

void read_settings(Table& t, CaseSpec& c, const std::string& section);
void read_fields(Table& t, Section& s) { read_settings(t, *s.spec, s.name); }

// The keys of `section`, its sub-sections, then the section's cross-key rules.
void read_settings(Table& t, CaseSpec& c, const std::string& section) {
  std::set<std::string> read;
  for (const SettingKey& key : case_keys()) {
    if (key.section != section) continue;
    read_key(t, c, key, read);
    if (key.path() == "dimension") t.ctx().dimension = c.dimension;  // the vectors and shapes depend on it
  }
  const std::string prefix = section.empty() ? "" : section + ".";
  for (const std::string& child : case_sections()) {
    if (child.size() <= prefix.size() || child.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string leaf = child.substr(prefix.size());
    if (leaf.find('.') != std::string::npos) continue;
    Section sub{&c, child};
    if (!t.read(leaf, sub)) t.ignore(leaf);
  }
  if (section.empty() && t.has("name") && c.name.empty()) t.problem("name", "must not be empty");
  if (section == "fluid") check_fluid(t, c);
  if (section == "fluid.ppe") check_ppe(t, c);
  if (section == "fluid.wcsph") check_wcsph(t, c);
}

void read_fields(Table& t, CaseSpec& c) {
  read_settings(t, c, "");
  t.read("periodic", c.periodic);
  t.read("materials", c.materials);
  t.read("bodies", c.bodies);
  t.read("loads", c.loads);
  t.read("probes", c.probes);
  t.read("open_boundaries", c.open_boundaries);
}

// ---------------------------------------------------------------------------------------------
// The resolved configuration, as TOML
// ---------------------------------------------------------------------------------------------

// An element of a list, as a table of the array `list` (its keys from list_schema.hpp).
void write_element(std::ostream& out, const std::string& list,
                   const std::vector<std::pair<std::string, std::string>>& entries) {
  out << "\n[[" << list << "]]\n";
  for (const auto& [key, value] : entries) out << key << " = " << value << "\n";
}

std::string resolved_toml(const CaseSpec& c) {
  const int d = c.dimension;
  std::ostringstream out;
  out << "# The case as run: overrides applied, every default written out.\n";
  for (const std::string& section : case_sections()) {
    if (!section.empty()) out << "\n[" << section << "]\n";
    for (const SettingKey& key : case_keys())
      if (key.section == section) out << key.name << " = " << key_text(key, c, d) << "\n";
  }
  if (const auto periodic = periodic_entries(c.periodic, d); !periodic.empty()) {  // only the periodic axes
    out << "\n[periodic]\n";
    for (const auto& [key, value] : periodic) out << key << " = " << value << "\n";
  }
  for (const auto& m : c.materials) write_element(out, "materials", material_entries(m, d));
  for (const auto& b : c.bodies) write_element(out, "bodies", body_entries(b, d));
  for (const auto& l : c.loads) write_element(out, "loads", load_entries(l, d));
  for (const auto& p : c.probes) write_element(out, "probes", probe_entries(p, d));
  for (const auto& o : c.open_boundaries) write_element(out, "open_boundaries", open_boundary_entries(o, d));
  return out.str();
}

// ---------------------------------------------------------------------------------------------

toml::value parse_file(const std::string& path) {
  std::error_code error;
  std::ifstream in(path, std::ios::binary);
  if (!in || std::filesystem::is_directory(path, error)) throw CaseError({path + ": cannot open file"});
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (const auto bad = first_invalid_utf8(text)) {
    const auto line = std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(*bad), '\n') + 1;
    throw CaseError({path + ": not UTF-8 text (line " + std::to_string(line) + ", byte " + std::to_string(*bad + 1) +
                     "): a case file is TOML, which is UTF-8"});
  }
  try {
    std::istringstream parsed(text);
    return toml::parse(parsed, path);
  } catch (const toml::exception& e) {
    throw CaseError({path + ": parse error: " + e.what()});
  }
}

}  // namespace

CaseError::CaseError(std::vector<std::string> problems)
    : std::runtime_error(join(problems, "\n")), problems_(std::move(problems)) {}

CaseSpec load_case(const std::string& path, const std::vector<std::string>& overrides) {
  toml::value doc = parse_file(path);
  Context ctx(path);
  for (const auto& text : overrides)
    if (const auto problem = apply_override(doc, text)) ctx.problems.push_back("--set " + text + ": " + *problem);

  CaseSpec c;
  c.source_path = path;
  c.name = std::filesystem::path(path).stem().string();
  convert(doc, "", ctx, c);
  check_lists(c, ctx);
  if (!ctx.problems.empty()) throw CaseError(std::move(ctx.problems));
  c.resolved_toml = resolved_toml(c);
  return c;
}

}  // namespace isph
