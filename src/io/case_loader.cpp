#include "io/case_loader.hpp"

#include <algorithm>
#include <charconv>
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

#include "io/case_schema.hpp"
#include "poisson/linear_solver.hpp"

namespace isph {

namespace {

using Vec3 = std::array<double, 3>;
using Choices = std::vector<std::string>;

enum class Need { optional, required };

// ---------------------------------------------------------------------------------------------
// Text helpers
// ---------------------------------------------------------------------------------------------

std::string join(const std::vector<std::string>& parts, const std::string& separator) {
  std::string text;
  for (std::size_t i = 0; i < parts.size(); ++i) text += (i ? separator : "") + parts[i];
  return text;
}

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

std::vector<std::string> split(const std::string& s, char separator) {
  std::vector<std::string> parts;
  std::istringstream in(s);
  for (std::string part; std::getline(in, part, separator);) parts.push_back(part);
  if (!s.empty() && s.back() == separator) parts.emplace_back();
  return parts;
}

std::string index_path(const std::string& path, std::size_t index) {
  return path + "[" + std::to_string(index) + "]";
}

std::string one_of(const Choices& allowed) {
  std::vector<std::string> quoted;
  for (const auto& choice : allowed) quoted.push_back(toml_string(choice));
  return "must be one of " + join(quoted, ", ");
}

std::string describe(const toml::value& v) {
  switch (v.type()) {
    case toml::value_t::boolean: return "a boolean";
    case toml::value_t::integer: return "an integer";
    case toml::value_t::floating: return "a float";
    case toml::value_t::string: return "a string";
    case toml::value_t::array: return "an array";
    case toml::value_t::table: return "a table";
    case toml::value_t::empty: return "nothing";
    default: return "a date or time";
  }
}

// ---------------------------------------------------------------------------------------------
// Reading: every problem is recorded in the Context, and reading goes on.
// ---------------------------------------------------------------------------------------------

struct Context {
  explicit Context(std::string file_name) : file(std::move(file_name)) {}

  std::string file;
  int dimension = 2;  // read first; vectors have this many components
  std::vector<std::string> problems;

  void problem(const std::string& key, const std::string& reason) {
    problems.push_back(file + ": " + key + ": " + reason);
  }
};

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
  Table(const toml::table& table, std::string path, Context& ctx)
      : table_(table), path_(std::move(path)), ctx_(ctx) {}
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
  for (std::size_t i = 0; i < items.size(); ++i)
    ok = convert(items[i], index_path(path, i), ctx, result[i]) && ok;
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
  for (std::size_t i = 0; i < items.size(); ++i)
    ok = convert(items[i], index_path(path, i), ctx, result[i]) && ok;
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

bool read_positive(Table& t, const std::string& key, double& out, Need need = Need::optional) {
  if (!t.read(key, out, need)) return false;
  if (out > 0.0) return true;
  t.problem(key, "must be > 0 (got " + shortest_number(out) + ")");
  return false;
}

void read_non_negative(Table& t, const std::string& key, double& out) {
  if (t.read(key, out) && out < 0.0) t.problem(key, "must be >= 0 (got " + shortest_number(out) + ")");
}

// Returns whether `out` holds a valid choice: the one read, or the default when the key is optional
// and absent.
bool read_choice(Table& t, const std::string& key, std::string& out, const Choices& allowed,
                 Need need = Need::optional) {
  std::string value;
  if (!t.read(key, value, need)) return need == Need::optional && !t.has(key);
  if (std::find(allowed.begin(), allowed.end(), value) == allowed.end()) {
    t.problem(key, one_of(allowed) + " (got " + toml_string(value) + ")");
    return false;
  }
  out = value;
  return true;
}

// The same for an enumeration's names (core/enum_names.hpp).
template <class E>
bool read_enum(Table& t, const std::string& key, E& out, Need need = Need::optional) {
  Choices allowed;
  for (const auto& entry : enum_names(E{})) allowed.emplace_back(entry.name);
  std::string name = name_of(out);
  if (!read_choice(t, key, name, allowed, need)) return false;
  out = *enum_from_name<E>(name);
  return true;
}

// A key that is not allowed here (given the values read before it): reported, and not read.
void reject(Table& t, const std::string& key, const std::string& reason) {
  if (!t.has(key)) return;
  t.ignore(key);
  t.problem(key, reason);
}

// A direction: any non-zero vector, stored normalized.
void read_direction(Table& t, const std::string& key, Vec3& out) {
  Vec3 d{};
  if (!t.read(key, d)) return;
  const double norm = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (norm == 0.0) {
    t.problem(key, "must not be the zero vector");
    return;
  }
  for (auto& c : d) c /= norm;
  out = d;
}

// ---------------------------------------------------------------------------------------------
// The schema (see case.hpp and docs/CASES.md)
// ---------------------------------------------------------------------------------------------

bool is_ball(const std::string& type) { return type == "circle" || type == "sphere"; }

// Each dimension has its own pair of shape types; one of the other dimension gets a pointed message.
bool check_shape_type(Table& t, const std::string& type) {
  const bool planar = t.ctx().dimension == 2;
  const Choices mine = planar ? Choices{"rectangle", "circle"} : Choices{"box", "sphere"};
  const Choices theirs = planar ? Choices{"box", "sphere"} : Choices{"rectangle", "circle"};
  const auto in = [&type](const Choices& choices) {
    return std::find(choices.begin(), choices.end(), type) != choices.end();
  };
  if (in(mine)) return true;
  if (in(theirs))
    t.problem("type", toml_string(type) + " is a " + (planar ? "3D" : "2D") +
                          " shape, but dimension = " + std::to_string(t.ctx().dimension) + "; " + one_of(mine));
  else
    t.problem("type", one_of(mine) + " (got " + toml_string(type) + ")");
  return false;
}

void read_fields(Table& t, Shape& s) {
  if (!t.read("type", s.type, Need::required) || !check_shape_type(t, s.type)) {
    t.ignore_rest();
    return;
  }
  if (is_ball(s.type)) {
    t.read("center", s.center, Need::required);
    read_positive(t, "radius", s.radius, Need::required);
    return;
  }
  const bool have_min = t.read("min", s.min, Need::required);
  if (!t.read("max", s.max, Need::required) || !have_min) return;
  for (int k = 0; k < t.ctx().dimension; ++k) {
    if (s.min[k] < s.max[k]) continue;
    t.problem("max", "must be > min in every component (component " + std::to_string(k) + ": min " +
                         shortest_number(s.min[k]) + ", max " + shortest_number(s.max[k]) + ")");
    return;
  }
}

// ---------------------------------------------------------------------------------------------
// The settings: read from the declared keys (case_schema.hpp), then each section's cross-key rules
// ---------------------------------------------------------------------------------------------

// The default surface thresholds on div r (case.hpp: FluidSpec).
double default_surface_threshold(int dimension) { return dimension == 2 ? 1.4 : 2.4; }
double default_surface_full(int dimension) { return dimension == 2 ? 1.6 : 2.6; }

// Reads one declared key if present; a value of the wrong type, out of bounds or not among the
// choices is reported and leaves the default.
template <class T>
void read_key_as(Table& t, CaseSpec& c, const CaseKey& key) {
  T value{};
  if (!t.read(key.name, value, key.required ? Need::required : Need::optional)) return;
  if constexpr (std::is_same_v<T, std::int64_t> || std::is_same_v<T, double>) {
    const bool integer = std::is_same_v<T, std::int64_t>;
    if (!key.bounds.admits(static_cast<double>(value))) {
      t.problem(key.name, "must be " + key.bounds.text(integer) + " (got " +
                              (integer ? std::to_string(value) : shortest_number(static_cast<double>(value))) + ")");
      return;
    }
    if (integer && (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max())) {
      t.problem(key.name, "must fit an int (got " + std::to_string(value) + ")");
      return;
    }
  }
  if constexpr (std::is_same_v<T, std::string>) {
    if (key.type == KeyType::choice && std::find(key.choices.begin(), key.choices.end(), value) == key.choices.end()) {
      t.problem(key.name, one_of(key.choices) + " (got " + toml_string(value) + ")");
      return;
    }
  }
  key.set(c, value);
}

void read_key(Table& t, CaseSpec& c, const CaseKey& key) {
  switch (key.type) {
    case KeyType::boolean:
      return read_key_as<bool>(t, c, key);
    case KeyType::integer:
      return read_key_as<std::int64_t>(t, c, key);
    case KeyType::number:
      return read_key_as<double>(t, c, key);
    case KeyType::vector:
      return read_key_as<Vec3>(t, c, key);
    default:
      return read_key_as<std::string>(t, c, key);
  }
}

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
  const Choices& methods = solver_methods(p.backend);
  if (std::find(methods.begin(), methods.end(), p.method) == methods.end())
    t.problem("method", toml_string(p.method) + " is not available with backend = " + toml_string(p.backend) + "; " +
                            one_of(methods));
  const Choices& preconditioners = solver_preconditioners(p.backend);
  if (!t.has("preconditioner"))
    p.preconditioner = preconditioners.front();
  else if (std::find(preconditioners.begin(), preconditioners.end(), p.preconditioner) == preconditioners.end())
    t.problem("preconditioner", toml_string(p.preconditioner) + " is not available with backend = " +
                                    toml_string(p.backend) + "; " + one_of(preconditioners));
  if (t.has("backend") && !t.has("fallback")) p.fallback = "none";
  if (p.fallback == p.backend)
    t.problem("fallback", "must differ from backend (both " + toml_string(p.backend) + "), or be \"none\"");
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
  for (const CaseKey& key : case_keys()) {
    if (key.section != section) continue;
    read_key(t, c, key);
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

// Each axis: [lo, hi] with hi > lo.
void read_fields(Table& t, PeriodicSpec& p) {
  static const char* const kAxes[] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    const std::string key = kAxes[k];
    if (k >= t.ctx().dimension) {
      reject(t, key, "only in 3D (dimension = " + std::to_string(t.ctx().dimension) + ")");
      continue;
    }
    std::vector<double> range;
    if (!t.read(key, range)) continue;
    if (range.size() != 2) {
      t.problem(key, "expected 2 numbers [lo, hi], got " + std::to_string(range.size()));
      continue;
    }
    if (!(range[1] > range[0])) {
      t.problem(key, "hi must be > lo (got [" + shortest_number(range[0]) + ", " + shortest_number(range[1]) + "])");
      continue;
    }
    p.axis[k] = true;
    p.lo[k] = range[0];
    p.hi[k] = range[1];
  }
}

// Poisson's ratio of a stable isotropic solid lies in (-1, 0.5); at 0.5 (incompressible) the bulk
// modulus and the P-wave speed are infinite.
void read_poisson_ratio(Table& t, double& nu) {
  if (!t.read("poisson_ratio", nu, Need::required)) return;
  if (!(nu > -1.0)) t.problem("poisson_ratio", "must be > -1 (got " + shortest_number(nu) + ")");
  if (!(nu < 0.5)) t.problem("poisson_ratio", "must be < 0.5 (got " + shortest_number(nu) + ")");
}

// Exactly one of youngs_modulus and bulk_modulus K; from K, E = 3K(1 - 2 nu).
void read_stiffness(Table& t, MaterialSpec& m) {
  const bool has_e = t.has("youngs_modulus");
  const bool has_k = t.has("bulk_modulus");
  if (has_e == has_k) {
    t.ignore("youngs_modulus");
    t.ignore("bulk_modulus");
    t.problem("youngs_modulus", has_e ? "give youngs_modulus or bulk_modulus, not both"
                                      : "missing required key (or give bulk_modulus)");
    return;
  }
  if (has_e) {
    read_positive(t, "youngs_modulus", m.youngs_modulus);
    return;
  }
  double bulk_modulus = 0.0;
  if (read_positive(t, "bulk_modulus", bulk_modulus))
    m.youngs_modulus = 3.0 * bulk_modulus * (1.0 - 2.0 * m.poisson_ratio);
}

void read_fields(Table& t, MaterialSpec& m) {
  t.read("name", m.name, Need::required);
  if (!read_choice(t, "model", m.model, {"saint_venant_kirchhoff", "newtonian"})) {
    m.model.clear();  // unknown: the other keys cannot be judged, nor the bodies that use it
    t.ignore_rest();
    return;
  }
  read_positive(t, "density", m.density, Need::required);
  if (m.model == "newtonian") {
    read_positive(t, "viscosity", m.viscosity, Need::required);
    for (const char* key : {"youngs_modulus", "bulk_modulus", "poisson_ratio", "plane"})
      reject(t, key, "only for saint_venant_kirchhoff (model = \"newtonian\")");
    return;
  }
  reject(t, "viscosity", "only for newtonian (model = \"saint_venant_kirchhoff\")");
  read_poisson_ratio(t, m.poisson_ratio);
  read_stiffness(t, m);
  if (t.ctx().dimension == 2) {
    read_enum(t, "plane", m.plane);
  } else if (t.has("plane")) {
    t.ignore("plane");
    t.problem("plane", "only used in 2D (dimension = 3)");
  }
}

void read_fields(Table& t, InitialVelocitySpec& v) {
  if (!read_enum(t, "type", v.type)) {
    t.ignore_rest();
    return;
  }
  if (v.type == InitialVelocityType::uniform) {
    t.read("value", v.value, Need::required);
  } else if (v.type == InitialVelocityType::cantilever_mode) {
    read_positive(t, "kL", v.kL);
    t.read("tip_velocity", v.tip_velocity, Need::required);
    read_positive(t, "length", v.length, Need::required);
    t.read("root", v.root);
    read_direction(t, "axis", v.axis);
    read_direction(t, "direction", v.direction);
  }
}

void read_fields(Table& t, MotionSpec& m) {
  if (!read_enum(t, "type", m.type, Need::required)) {
    t.ignore_rest();
    return;
  }
  if (m.type == MotionType::none) return;
  if (m.type == MotionType::constant_velocity) {
    t.read("velocity", m.velocity, Need::required);
    return;
  }
  if (m.type == MotionType::translation) {
    read_direction(t, "direction", m.direction);
  } else if (t.ctx().dimension != 2) {
    t.problem("type", "\"rotation\" is only for dimension = 2 (dimension = " + std::to_string(t.ctx().dimension) + ")");
    t.ignore_rest();
    return;
  } else {
    t.read("pivot", m.pivot, Need::required);
  }
  if (!read_enum(t, "profile", m.profile, Need::required)) {
    t.ignore_rest();
    return;
  }
  if (m.profile == MotionLaw::polynomial) {
    if (t.read("coefficients", m.coefficients, Need::required) && m.coefficients.empty())
      t.problem("coefficients", "must not be empty");
    read_non_negative(t, "until", m.until);
  } else if (m.profile == MotionLaw::sine) {
    t.read("amplitude", m.amplitude, Need::required);
    read_positive(t, "period", m.period, Need::required);
    t.read("phase", m.phase);
  } else {
    t.read("file", m.file, Need::required);
  }
}

constexpr std::pair<const char*, ParticleKind> kKinds[] = {
    {"fluid", ParticleKind::fluid}, {"wall", ParticleKind::wall}, {"structure", ParticleKind::structure}};

std::string kind_name(ParticleKind kind) {
  for (const auto& [name, k] : kKinds)
    if (k == kind) return name;
  return "";
}

ParticleKind kind_from_name(const std::string& name) {
  for (const auto& [n, kind] : kKinds)
    if (name == n) return kind;
  return ParticleKind::structure;
}

// The lattice is anchored at the lower corner of the shape's bounding box.
Vec3 default_lattice_origin(const Shape& s, int dimension) {
  if (!is_ball(s.type)) return s.min;
  Vec3 origin{};
  for (int k = 0; k < dimension; ++k) origin[k] = s.center[k] - s.radius;
  return origin;
}

void read_fields(Table& t, BodySpec& b) {
  t.read("name", b.name, Need::required);
  std::string kind = kind_name(b.kind);
  if (read_choice(t, "kind", kind, {"fluid", "wall", "structure"})) b.kind = kind_from_name(kind);
  const bool wall = b.kind == ParticleKind::wall;
  const std::string kind_is = "kind = " + toml_string(kind_name(b.kind));
  // Structures need an elastic material and fluids a newtonian one (check_lists); walls may name one.
  t.read("material", b.material, wall ? Need::optional : Need::required);
  t.read("shape", b.shape, Need::required);
  if (b.kind == ParticleKind::structure) {
    t.read("clamps", b.clamps);
    if (t.read("refinement", b.refinement) && !(b.refinement >= 1.0 && b.refinement <= 16.0))
      t.problem("refinement",
                "must be in [1, 16]: the structure's spacing is dx / refinement, finer than the "
                "water's or equal (got " +
                    shortest_number(b.refinement) + ")");
    if (read_positive(t, "dx", b.dx) && t.has("refinement"))
      t.problem("dx", "give the body's spacing as dx or as refinement, not both");
  } else {
    reject(t, "clamps", "only for kind = \"structure\" (" + kind_is + ")");
    reject(t, "refinement", "only for kind = \"structure\"; fluid and walls take the case's dx (" + kind_is + ")");
    reject(t, "dx", "only for kind = \"structure\"; fluid and walls take the case's dx (" + kind_is + ")");
  }
  b.lattice_origin = default_lattice_origin(b.shape, t.ctx().dimension);
  t.read("lattice_origin", b.lattice_origin);
  if (t.read("lattice_offset", b.lattice_offset))
    for (int k = 0; k < t.ctx().dimension; ++k)
      if (!(b.lattice_offset[k] >= 0.0 && b.lattice_offset[k] < 1.0)) {
        t.problem("lattice_offset", "every component must be in [0, 1), in units of the body's spacing (got " +
                                        shortest_number(b.lattice_offset[k]) + " in component " + std::to_string(k) +
                                        ")");
        break;
      }
  if (wall) {
    reject(t, "initial_velocity", "not for kind = \"wall\" (use motion)");
  } else if (t.read("initial_velocity", b.initial_velocity) && b.kind == ParticleKind::fluid &&
             b.initial_velocity.type == InitialVelocityType::cantilever_mode) {
    t.problem("initial_velocity",
              "type \"cantilever_mode\" is only for kind = \"structure\"; "
              "a fluid takes \"none\" or \"uniform\"");
  }
  if (b.kind == ParticleKind::fluid)
    reject(t, "motion", "only for kind = \"wall\" or \"structure\" (" + kind_is + "; see initial_velocity)");
  else
    t.read("motion", b.motion);
}

void read_fields(Table& t, LoadSpec& l) {
  if (!read_enum(t, "type", l.type, Need::required)) {
    t.ignore_rest();
    return;
  }
  t.read("body", l.body, Need::required);
  if (l.type == LoadType::edge) {
    t.read("region", l.region, Need::required);
    t.read("force", l.force, Need::required);
  } else if (l.type == LoadType::traction) {
    t.read("region", l.region, Need::required);
    t.read("traction", l.traction, Need::required);
  } else if (l.type == LoadType::point) {
    // A point load is given by `point`; it is kept as the centre of a "point" region.
    l.region.type = "point";
    t.read("point", l.region.center, Need::required);
    t.read("force", l.force, Need::required);
  } else {
    t.read("acceleration", l.acceleration, Need::required);
  }
  read_non_negative(t, "ramp_time", l.ramp_time);
}

// Probe names become column names and file names.
bool is_identifier(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

void read_fields(Table& t, ProbeSpec& p) {
  if (t.read("name", p.name, Need::required) && !is_identifier(p.name))
    t.problem("name", "must match [A-Za-z0-9_]+ (got " + toml_string(p.name) + ")");
  read_enum(t, "type", p.type);
  t.read("point", p.point, p.type == ProbeType::max_speed ? Need::optional : Need::required);
}

void read_fields(Table& t, CaseSpec& c) {
  read_settings(t, c, "");
  t.read("periodic", c.periodic);
  t.read("materials", c.materials);
  t.read("bodies", c.bodies);
  t.read("loads", c.loads);
  t.read("probes", c.probes);
}

// ---------------------------------------------------------------------------------------------
// Checks across lists
// ---------------------------------------------------------------------------------------------

template <class Spec>
void check_unique_names(const std::vector<Spec>& items, const std::string& list, Context& ctx) {
  std::map<std::string, std::size_t> first;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (items[i].name.empty()) continue;  // missing: reported already
    const auto [it, inserted] = first.emplace(items[i].name, i);
    if (!inserted)
      ctx.problem(index_path(list, i) + ".name",
                  "duplicate name " + toml_string(items[i].name) + " (also " + index_path(list, it->second) + ")");
  }
}

// `name` must be the name of one of `items`.
template <class Spec>
void check_reference(const std::string& name, const std::vector<Spec>& items, const std::string& what,
                     const std::string& path, Context& ctx) {
  if (name.empty()) return;  // missing: reported already
  std::vector<std::string> known;
  for (const auto& item : items) {
    if (item.name == name) return;
    if (!item.name.empty()) known.push_back(toml_string(item.name));
  }
  ctx.problem(path, "no " + what + " named " + toml_string(name) +
                        (known.empty() ? " (none defined)" : " (known: " + join(known, ", ") + ")"));
}

// A structure needs an elastic material, a fluid a newtonian one.
void check_material_model(const BodySpec& b, const std::vector<MaterialSpec>& materials,
                          const std::string& path, Context& ctx) {
  if (b.kind == ParticleKind::wall) return;
  const std::string needed = b.kind == ParticleKind::fluid ? "newtonian" : "saint_venant_kirchhoff";
  for (const auto& m : materials) {
    if (m.name != b.material) continue;
    if (!m.model.empty() && m.model != needed)  // empty: an unknown model, reported already
      ctx.problem(path, "material " + toml_string(m.name) + " has model = " + toml_string(m.model) + ", but a " +
                            kind_name(b.kind) + " body needs model = " + toml_string(needed));
    return;  // a duplicate name is reported already
  }
}

// The first body of `kind` (its path and name, for messages), or "" if there is none.
std::string first_body(const std::vector<BodySpec>& bodies, ParticleKind kind) {
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].kind == kind) return index_path("bodies", i) + " " + toml_string(bodies[i].name);
  return "";
}

// Which stages run follows from the bodies. A case without structures that runs the fluid stage
// does not run the structure stage, whatever stages.structure says (its default is true).
void check_stages(CaseSpec& c, Context& ctx) {
  const std::string fluid = first_body(c.bodies, ParticleKind::fluid);
  const std::string structure = first_body(c.bodies, ParticleKind::structure);
  if (structure.empty() && c.stages.fluid) c.stages.structure = false;
  if (c.stages.fluid && fluid.empty())
    ctx.problem("stages.fluid", "needs at least one body of kind = \"fluid\"");
  if (!c.stages.fluid && !fluid.empty())
    ctx.problem("stages.fluid", "the case has fluid bodies (" + fluid + "); set stages.fluid = true");
  if (c.stages.structure && structure.empty())
    ctx.problem("stages.structure",
                "needs at least one body of kind = \"structure\" (or set stages.fluid = true "
                "for a fluid case)");
  if (!c.stages.structure && !structure.empty())
    ctx.problem("stages.structure",
                "the case has structure bodies (" + structure + "); set stages.structure = true");
  if (!c.stages.structure && !c.stages.fluid)
    ctx.problem("stages", "nothing to run: set stages.structure or stages.fluid to true");
  for (std::size_t i = 0; i < c.probes.size(); ++i) {
    const std::string type = name_of(c.probes[i].type);
    const bool structural = c.probes[i].type == ProbeType::displacement;
    if (structural ? c.stages.structure : c.stages.fluid) continue;
    ctx.problem(index_path("probes", i) + ".type",
                toml_string(type) + " probes need stages." + (structural ? "structure" : "fluid") + " = true");
  }
}

// The rows "time, value" of a motion file: numbers separated by commas, tabs, semicolons or spaces;
// blank lines and lines starting with '#' are skipped, and so is a first line that is not numeric (a
// header). Returns false, with the problem in ctx under `path`, for a file that cannot serve.
bool read_motion_rows(const std::string& file, const std::string& path, Context& ctx, MotionSpec& m) {
  std::ifstream in(file);
  if (!in) {
    ctx.problem(path, "cannot open " + toml_string(file));
    return false;
  }
  std::string line;
  int line_number = 0;
  bool first = true;
  while (std::getline(in, line)) {
    ++line_number;
    std::string spaced = line;
    for (char& ch : spaced)
      if (ch == ',' || ch == '\t' || ch == ';' || ch == '\r') ch = ' ';
    std::istringstream fields(spaced);
    std::vector<double> numbers;
    std::string item;
    bool numeric = true;
    while (fields >> item) {
      double x = 0;
      const auto [ptr, error] = std::from_chars(item.data(), item.data() + item.size(), x);
      if (error != std::errc() || ptr != item.data() + item.size() || !std::isfinite(x)) numeric = false;
      numbers.push_back(x);
    }
    if (numbers.empty() || trim(line).front() == '#') continue;
    const bool header = first && !numeric;
    first = false;
    if (header) continue;
    if (!numeric || numbers.size() != 2) {
      ctx.problem(path, toml_string(file) + " line " + std::to_string(line_number) +
                            ": expected two numbers, time and value (got " + toml_string(trim(line)) + ")");
      return false;
    }
    if (!m.times.empty() && !(numbers[0] > m.times.back())) {
      ctx.problem(path, toml_string(file) + " line " + std::to_string(line_number) +
                            ": the rows must be sorted by time, " + "strictly increasing (t = " +
                            shortest_number(numbers[0]) + " follows t = " + shortest_number(m.times.back()) + ")");
      return false;
    }
    m.times.push_back(numbers[0]);
    m.values.push_back(numbers[1]);
  }
  if (m.times.size() >= 2) return true;
  ctx.problem(path, toml_string(file) + ": needs at least two rows (got " + std::to_string(m.times.size()) + ")");
  return false;
}

// Motion files are read here, where the case file's folder and end_time are known: a file must reach
// end_time (before its first row the first value holds). The resolved configuration names the file by
// its absolute path.
void read_motion_files(CaseSpec& c, Context& ctx) {
  const auto folder = std::filesystem::path(c.source_path).parent_path();
  for (std::size_t i = 0; i < c.bodies.size(); ++i) {
    BodySpec& b = c.bodies[i];
    const std::string path = index_path("bodies", i) + ".motion";
    if (b.kind == ParticleKind::structure && b.motion.type != MotionType::none && b.clamps.empty())
      ctx.problem(path, "moves the clamped particles of a structure, and this body has no clamps");
    MotionSpec& m = b.motion;
    if ((m.type != MotionType::translation && m.type != MotionType::rotation) || m.profile != MotionLaw::csv ||
        m.file.empty())
      continue;
    std::filesystem::path file(m.file);
    if (file.is_relative()) file = folder / file;
    m.file = std::filesystem::absolute(file).lexically_normal().string();
    if (!read_motion_rows(m.file, path + ".file", ctx, m)) continue;
    if (m.times.back() < c.end_time)
      ctx.problem(path + ".file", toml_string(m.file) + " ends at t = " + shortest_number(m.times.back()) +
                                      " s, before end_time = " + shortest_number(c.end_time) + " s");
  }
}

void check_lists(CaseSpec& c, Context& ctx) {
  read_motion_files(c, ctx);
  check_unique_names(c.materials, "materials", ctx);
  check_unique_names(c.bodies, "bodies", ctx);
  check_unique_names(c.probes, "probes", ctx);
  for (std::size_t i = 0; i < c.bodies.size(); ++i) {
    const std::string path = index_path("bodies", i) + ".material";
    check_reference(c.bodies[i].material, c.materials, "material", path, ctx);
    check_material_model(c.bodies[i], c.materials, path, ctx);
  }
  for (std::size_t i = 0; i < c.loads.size(); ++i)
    check_reference(c.loads[i].body, c.bodies, "body", index_path("loads", i) + ".body", ctx);
  check_stages(c, ctx);
}

// ---------------------------------------------------------------------------------------------
// Overrides
// ---------------------------------------------------------------------------------------------

// The offset of the first byte of `text` that does not belong to a well-formed UTF-8 sequence (Unicode
// 15, Table 3-7: no overlong forms, no surrogates, nothing above U+10FFFF), or none. TOML is UTF-8, and
// toml11 3.7's parser reads out of bounds on some malformed sequences (found by fuzzing, docs/RELIABILITY.md),
// so text is checked before it is parsed.
std::optional<std::size_t> first_invalid_utf8(std::string_view text) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char b = byte(i);
    // The sequence's length and the allowed range of its second byte, from its lead byte.
    std::size_t length = 1;
    unsigned char low = 0x80, high = 0xBF;
    if (b >= 0x80) {
      if (b >= 0xC2 && b <= 0xDF) {
        length = 2;
      } else if (b >= 0xE0 && b <= 0xEF) {
        length = 3;
        low = b == 0xE0 ? 0xA0 : 0x80;
        high = b == 0xED ? 0x9F : 0xBF;
      } else if (b >= 0xF0 && b <= 0xF4) {
        length = 4;
        low = b == 0xF0 ? 0x90 : 0x80;
        high = b == 0xF4 ? 0x8F : 0xBF;
      } else {
        return i;
      }
    }
    if (i + length > text.size()) return i;
    for (std::size_t k = 1; k < length; ++k) {
      const unsigned char c = byte(i + k);
      if (k == 1 ? (c < low || c > high) : (c < 0x80 || c > 0xBF)) return i;
    }
    i += length;
  }
  return std::nullopt;
}

// The value of an override: a TOML value if the text is one, else the text itself as a string (so
// that `structure.integrator=verlet` works unquoted).
toml::value override_value(const std::string& text) {
  std::istringstream in("v = " + text);
  try {
    const toml::value doc = toml::parse(in, "--set");
    if (doc.as_table().size() == 1) return doc.at("v");
  } catch (const std::exception&) {
    // not a TOML value: taken as a string below
  }
  return toml::value(text);
}

// The element of an array named by `segment`: a numeric index, or else the table whose `name` is
// `segment`. Null if there is none.
toml::value* array_element(toml::array& items, const std::string& segment) {
  std::size_t index = 0;
  const char* end = segment.data() + segment.size();
  const auto [ptr, error] = std::from_chars(segment.data(), end, index);
  if (error == std::errc() && ptr == end) return index < items.size() ? &items[index] : nullptr;
  for (auto& item : items)
    if (item.is_table() && item.contains("name") && item.at("name").is_string() &&
        item.at("name").as_string().str == segment)
      return &item;
  return nullptr;
}

// Sets "dotted.key=value" in `doc`. Missing table keys are created, so that a key outside the
// schema is reported as unknown by the reading that follows. Returns the problem, if any.
std::optional<std::string> apply_override(toml::value& doc, const std::string& text) {
  if (const auto bad = first_invalid_utf8(text)) return "not UTF-8 text (byte " + std::to_string(*bad + 1) + ")";
  const auto equals = text.find('=');
  if (equals == std::string::npos) return "expected key=value";
  const auto segments = split(trim(text.substr(0, equals)), '.');
  if (segments.empty() || std::find(segments.begin(), segments.end(), "") != segments.end())
    return "expected key=value (with a key like kernel.h_factor)";
  toml::value* node = &doc;
  std::string walked;
  for (const auto& segment : segments) {
    if (node->is_table()) {
      node = &node->as_table().try_emplace(segment, toml::table{}).first->second;
    } else if (node->is_array()) {
      node = array_element(node->as_array(), segment);
      if (!node) return walked + ": no element with index or name " + toml_string(segment);
    } else {
      return walked + ": is " + describe(*node) + ", not a table or an array";
    }
    walked += (walked.empty() ? "" : ".") + segment;
  }
  *node = override_value(trim(text.substr(equals + 1)));
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------------
// The resolved configuration, as TOML
// ---------------------------------------------------------------------------------------------

std::string toml_vector(const Vec3& v, int dimension) {
  std::vector<std::string> items;
  for (int k = 0; k < dimension; ++k) items.push_back(toml_float(v[k]));
  return "[" + join(items, ", ") + "]";
}

std::string inline_table(const std::vector<std::pair<std::string, std::string>>& entries) {
  std::vector<std::string> items;
  for (const auto& [key, value] : entries) items.push_back(key + " = " + value);
  return "{ " + join(items, ", ") + " }";
}

std::string toml_shape(const Shape& s, int dimension) {
  if (is_ball(s.type))
    return inline_table({{"type", toml_string(s.type)},
                         {"center", toml_vector(s.center, dimension)},
                         {"radius", toml_float(s.radius)}});
  return inline_table(
      {{"type", toml_string(s.type)}, {"min", toml_vector(s.min, dimension)}, {"max", toml_vector(s.max, dimension)}});
}

std::string toml_velocity(const InitialVelocitySpec& v, int dimension) {
  const std::string type = toml_string(name_of(v.type));
  if (v.type == InitialVelocityType::uniform)
    return inline_table({{"type", type}, {"value", toml_vector(v.value, dimension)}});
  if (v.type == InitialVelocityType::cantilever_mode)
    return inline_table({{"type", type},
                         {"kL", toml_float(v.kL)},
                         {"tip_velocity", toml_float(v.tip_velocity)},
                         {"length", toml_float(v.length)},
                         {"root", toml_vector(v.root, dimension)},
                         {"axis", toml_vector(v.axis, dimension)},
                         {"direction", toml_vector(v.direction, dimension)}});
  return inline_table({{"type", type}});
}

std::string toml_motion(const MotionSpec& m, int dimension) {
  std::vector<std::pair<std::string, std::string>> entries{{"type", toml_string(name_of(m.type))}};
  if (m.type == MotionType::constant_velocity) entries.emplace_back("velocity", toml_vector(m.velocity, dimension));
  if (m.type == MotionType::translation) entries.emplace_back("direction", toml_vector(m.direction, dimension));
  if (m.type == MotionType::rotation) entries.emplace_back("pivot", toml_vector(m.pivot, dimension));
  if (m.type == MotionType::translation || m.type == MotionType::rotation) {
    entries.emplace_back("profile", toml_string(name_of(m.profile)));
    if (m.profile == MotionLaw::polynomial) {
      std::vector<std::string> items;
      for (double c : m.coefficients) items.push_back(toml_float(c));
      entries.emplace_back("coefficients", "[" + join(items, ", ") + "]");
      entries.emplace_back("until", toml_float(m.until));
    } else if (m.profile == MotionLaw::sine) {
      entries.emplace_back("amplitude", toml_float(m.amplitude));
      entries.emplace_back("period", toml_float(m.period));
      entries.emplace_back("phase", toml_float(m.phase));
    } else {
      entries.emplace_back("file", toml_string(m.file));
    }
  }
  return inline_table(entries);
}

void write_material(std::ostream& out, const MaterialSpec& m, int dimension) {
  out << "\n[[materials]]\n"
      << "name = " << toml_string(m.name) << "\n"
      << "model = " << toml_string(m.model) << "\n"
      << "density = " << toml_float(m.density) << "\n";
  if (m.model == "newtonian") {
    out << "viscosity = " << toml_float(m.viscosity) << "\n";
    return;
  }
  out << "youngs_modulus = " << toml_float(m.youngs_modulus) << "\n"
      << "poisson_ratio = " << toml_float(m.poisson_ratio) << "\n";
  if (dimension == 2) out << "plane = " << toml_string(name_of(m.plane)) << "\n";
}

void write_body(std::ostream& out, const BodySpec& b, int dimension) {
  std::vector<std::string> clamps;
  for (const auto& clamp : b.clamps) clamps.push_back(toml_shape(clamp, dimension));
  out << "\n[[bodies]]\n"
      << "name = " << toml_string(b.name) << "\n"
      << "kind = " << toml_string(kind_name(b.kind)) << "\n";
  if (!b.material.empty()) out << "material = " << toml_string(b.material) << "\n";
  out << "shape = " << toml_shape(b.shape, dimension) << "\n";
  if (b.kind == ParticleKind::structure) out << "clamps = [" << join(clamps, ", ") << "]\n"
                                              << (b.dx > 0 ? "dx = " + toml_float(b.dx) : "refinement = " + toml_float(b.refinement))
                                              << "\n";
  out << "lattice_origin = " << toml_vector(b.lattice_origin, dimension) << "\n";
  out << "lattice_offset = " << toml_vector(b.lattice_offset, dimension) << "\n";
  if (b.kind != ParticleKind::wall) out << "initial_velocity = " << toml_velocity(b.initial_velocity, dimension) << "\n";
  if (b.kind != ParticleKind::fluid) out << "motion = " << toml_motion(b.motion, dimension) << "\n";
}

void write_load(std::ostream& out, const LoadSpec& l, int dimension) {
  out << "\n[[loads]]\n"
      << "type = " << toml_string(name_of(l.type)) << "\n"
      << "body = " << toml_string(l.body) << "\n";
  if (l.type == LoadType::edge || l.type == LoadType::traction)
    out << "region = " << toml_shape(l.region, dimension) << "\n";
  if (l.type == LoadType::point) out << "point = " << toml_vector(l.region.center, dimension) << "\n";
  if (l.type == LoadType::body)
    out << "acceleration = " << toml_vector(l.acceleration, dimension) << "\n";
  else if (l.type == LoadType::traction)
    out << "traction = " << toml_vector(l.traction, dimension) << "\n";
  else
    out << "force = " << toml_vector(l.force, dimension) << "\n";
  out << "ramp_time = " << toml_float(l.ramp_time) << "\n";
}

void write_probe(std::ostream& out, const ProbeSpec& p, int dimension) {
  out << "\n[[probes]]\n"
      << "name = " << toml_string(p.name) << "\n"
      << "type = " << toml_string(name_of(p.type)) << "\n"
      << "point = " << toml_vector(p.point, dimension) << "\n";
}

// Only the periodic axes; no table when there are none.
void write_periodic(std::ostream& out, const PeriodicSpec& p, int dimension) {
  static const char* const kAxes[] = {"x", "y", "z"};
  if (std::none_of(p.axis.begin(), p.axis.begin() + dimension, [](bool periodic) { return periodic; }))
    return;
  out << "\n[periodic]\n";
  for (int k = 0; k < dimension; ++k)
    if (p.axis[k]) out << kAxes[k] << " = [" << toml_float(p.lo[k]) << ", " << toml_float(p.hi[k]) << "]\n";
}

std::string resolved_toml(const CaseSpec& c) {
  const int d = c.dimension;
  std::ostringstream out;
  out << "# The case as run: overrides applied, every default written out.\n";
  for (const std::string& section : case_sections()) {
    if (!section.empty()) out << "\n[" << section << "]\n";
    for (const CaseKey& key : case_keys())
      if (key.section == section) out << key.name << " = " << toml_value(key.get(c), d) << "\n";
  }
  write_periodic(out, c.periodic, d);
  for (const auto& m : c.materials) write_material(out, m, d);
  for (const auto& b : c.bodies) write_body(out, b, d);
  for (const auto& l : c.loads) write_load(out, l, d);
  for (const auto& p : c.probes) write_probe(out, p, d);
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
    if (const auto problem = apply_override(doc, text))
      ctx.problems.push_back("--set " + text + ": " + *problem);

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
