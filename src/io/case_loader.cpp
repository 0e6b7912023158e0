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
#include <utility>

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

// The shortest text that reads back as the same double.
std::string show(double x) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

// A TOML basic string.
std::string quote(const std::string& s) {
  std::string text = "\"";
  for (const char ch : s) {
    const auto code = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      text += '\\';
      text += ch;
    } else if (code < 0x20 || code == 0x7f) {
      char escape[8];
      std::snprintf(escape, sizeof escape, "\\u%04x", code);
      text += escape;
    } else {
      text += ch;
    }
  }
  return text + "\"";
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
  for (const auto& choice : allowed) quoted.push_back(quote(choice));
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
    ctx.problem(path, "must be finite (got " + show(x) + ")");
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

// A point or vector: exactly `dimension` numbers; the unused components stay zero.
bool convert(const toml::value& v, const std::string& path, Context& ctx, Vec3& out) {
  const std::string expected = std::to_string(ctx.dimension) + " numbers";
  if (!v.is_array()) return mismatch(v, "an array of " + expected, path, ctx);
  const auto& items = v.as_array();
  if (items.size() != static_cast<std::size_t>(ctx.dimension)) {
    ctx.problem(path, "expected " + expected + " (dimension = " + std::to_string(ctx.dimension) + "), got " +
                          std::to_string(items.size()));
    return false;
  }
  Vec3 result{};
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
  t.problem(key, "must be > 0 (got " + show(out) + ")");
  return false;
}

void read_non_negative(Table& t, const std::string& key, double& out) {
  if (t.read(key, out) && out < 0.0) t.problem(key, "must be >= 0 (got " + show(out) + ")");
}

// Returns whether `out` holds a valid choice: the one read, or the default when the key is optional
// and absent.
bool read_choice(Table& t, const std::string& key, std::string& out, const Choices& allowed,
                 Need need = Need::optional) {
  std::string value;
  if (!t.read(key, value, need)) return need == Need::optional && !t.has(key);
  if (std::find(allowed.begin(), allowed.end(), value) == allowed.end()) {
    t.problem(key, one_of(allowed) + " (got " + quote(value) + ")");
    return false;
  }
  out = value;
  return true;
}

// A key that is not allowed here (given the values read before it): reported, and not read.
void reject(Table& t, const std::string& key, const std::string& reason) {
  if (!t.has(key)) return;
  t.ignore(key);
  t.problem(key, reason);
}

// An integer > 0 that fits an int.
void read_positive_int(Table& t, const std::string& key, int& out) {
  std::int64_t value = out;
  if (!t.read(key, value)) return;
  if (value <= 0)
    t.problem(key, "must be > 0 (got " + std::to_string(value) + ")");
  else if (value > std::numeric_limits<int>::max())
    t.problem(key, "must be <= " + std::to_string(std::numeric_limits<int>::max()) + " (got " +
                       std::to_string(value) + ")");
  else
    out = static_cast<int>(value);
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
    t.problem("type", quote(type) + " is a " + (planar ? "3D" : "2D") + " shape, but dimension = " +
                          std::to_string(t.ctx().dimension) + "; " + one_of(mine));
  else
    t.problem("type", one_of(mine) + " (got " + quote(type) + ")");
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
                         show(s.min[k]) + ", max " + show(s.max[k]) + ")");
    return;
  }
}

void read_fields(Table& t, KernelSpec& k) {
  read_choice(t, "type", k.type, {"cubic_spline", "wendland_c2"});
  read_positive(t, "h_factor", k.h_factor);
  t.read("correction", k.correction);
}

void read_fields(Table& t, StructureSpec& s) {
  read_choice(t, "integrator", s.integrator, {"rk4", "verlet"});
  read_choice(t, "gradient", s.gradient, {"linear", "quadratic"});
  read_choice(t, "quadrature", s.quadrature, {"point", "cell"});
  read_positive(t, "courant", s.courant);
  read_non_negative(t, "damping", s.damping);
  read_non_negative(t, "hourglass", s.hourglass);
}

void read_fields(Table& t, CouplingSpec& c) {
  std::int64_t substeps = c.substeps;
  if (t.read("substeps", substeps)) {
    if (substeps < 0 || substeps > 1000000)
      t.problem("substeps", "must be 0 (from the structure's stability limit) or a count in 1..1000000 (got " +
                                std::to_string(substeps) + ")");
    else
      c.substeps = static_cast<int>(substeps);
  }
  t.read("fsi_shifting", c.fsi_shifting);
  t.read("wall_contact", c.wall_contact);
  t.read("implicit_added_mass", c.implicit_added_mass);
  read_choice(t, "interaction_force", c.interaction_force, {"gradient", "pairwise"});
  read_choice(t, "substep_interaction", c.substep_interaction, {"held", "interpolated"});
  if (t.read("tolerance", c.tolerance) && !(c.tolerance > 0.0 && c.tolerance < 1.0))
    t.problem("tolerance", "must be > 0 and < 1 (got " + show(c.tolerance) + ")");
  read_positive_int(t, "max_iterations", c.max_iterations);
  if (t.read("first_ppe_tolerance", c.first_ppe_tolerance) &&
      !(c.first_ppe_tolerance >= 0.0 && c.first_ppe_tolerance < 1.0))
    t.problem("first_ppe_tolerance",
              "must be 0 (the PPE's tolerance) or > 0 and < 1 (got " + show(c.first_ppe_tolerance) + ")");
  std::int64_t reuse = c.reuse_steps;
  if (t.read("reuse_steps", reuse)) {
    if (reuse < 0 || reuse > 100)
      t.problem("reuse_steps", "must be in 0..100 (got " + std::to_string(reuse) + ")");
    else
      c.reuse_steps = static_cast<int>(reuse);
  }
}

void read_fields(Table& t, OutputSpec& o) {
  read_non_negative(t, "interval", o.interval);
  read_non_negative(t, "snapshot_interval", o.snapshot_interval);
  t.read("snapshots", o.snapshots);
}

void read_fields(Table& t, StagesSpec& s) {
  t.read("structure", s.structure);
  t.read("fluid", s.fluid);
}

void read_fields(Table& t, ShiftingSpec& s) {
  read_choice(t, "type", s.type, {"none", "xu", "ops"});
  if (read_positive(t, "coefficient", s.coefficient) && s.coefficient > 1.0)
    t.problem("coefficient", "must be <= 1 (got " + show(s.coefficient) + ")");
  read_positive(t, "max_fraction", s.max_fraction);
  t.read("taylor_correction", s.taylor_correction);
}

// Every option any backend offers (poisson/linear_solver.hpp), in catalogue order.
template <class Options>
Choices any_backend(Options options) {
  Choices all;
  for (const std::string& b : solver_backends())
    for (const std::string& o : options(b))
      if (std::find(all.begin(), all.end(), o) == all.end()) all.push_back(o);
  return all;
}

void read_fields(Table& t, PpeSolverSpec& p) {
  // The options of every backend, then those of the chosen one.
  const bool backend_ok = read_choice(t, "backend", p.backend, solver_backends());
  if (read_choice(t, "method", p.method, any_backend(solver_methods)) && backend_ok) {
    const Choices& allowed = solver_methods(p.backend);
    if (std::find(allowed.begin(), allowed.end(), p.method) == allowed.end())
      t.problem("method", quote(p.method) + " is not available with backend = " + quote(p.backend) + "; " +
                              one_of(allowed));
  }
  if (!t.has("preconditioner")) p.preconditioner = solver_preconditioners(p.backend).front();
  if (read_choice(t, "preconditioner", p.preconditioner, any_backend(solver_preconditioners)) &&
      backend_ok && t.has("preconditioner")) {
    const Choices& allowed = solver_preconditioners(p.backend);
    if (std::find(allowed.begin(), allowed.end(), p.preconditioner) == allowed.end())
      t.problem("preconditioner", quote(p.preconditioner) + " is not available with backend = " +
                                      quote(p.backend) + "; " + one_of(allowed));
  }
  if (t.read("tolerance", p.tolerance) && !(p.tolerance > 0.0 && p.tolerance < 1.0))
    t.problem("tolerance", "must be > 0 and < 1 (got " + show(p.tolerance) + ")");
  read_positive_int(t, "max_iterations", p.max_iterations);
  if (t.has("backend") && !t.has("fallback")) p.fallback = "none";  // case.hpp: the default pair is kept whole
  if (read_choice(t, "fallback", p.fallback, {"none", "eigen", "hypre"}) && backend_ok &&
      p.fallback == p.backend)
    t.problem("fallback", "must differ from backend (both " + quote(p.backend) + "), or be \"none\"");
  std::int64_t reuse = p.preconditioner_reuse;
  if (t.read("preconditioner_reuse", reuse)) {
    if (reuse < 0 || reuse > 1000)
      t.problem("preconditioner_reuse", "must be in 0..1000 steps (got " + std::to_string(reuse) + ")");
    else
      p.preconditioner_reuse = static_cast<int>(reuse);
  }
}

// The default surface thresholds on div r (case.hpp: FluidSpec).
double default_surface_threshold(int dimension) { return dimension == 2 ? 1.4 : 2.4; }
double default_surface_full(int dimension) { return dimension == 2 ? 1.6 : 2.6; }

void read_fields(Table& t, WcsphSpec& w) {
  read_choice(t, "time_stepping", w.time_stepping, {"dual_criteria", "single_criterion"});
  read_positive(t, "advection_courant", w.advection_courant);
  if (!t.has("acoustic_courant"))  // seed 002 §2.2: 0.6 with dual-criteria stepping, 0.25 without
    w.acoustic_courant = w.time_stepping == "dual_criteria" ? 0.6 : 0.25;
  read_positive(t, "acoustic_courant", w.acoustic_courant);
  read_non_negative(t, "sound_speed", w.sound_speed);
  read_non_negative(t, "riemann_limiter", w.riemann_limiter);
}

void read_fields(Table& t, FluidSpec& f) {
  read_choice(t, "model", f.model, {"isph", "wcsph"});
  read_positive(t, "courant", f.courant);
  read_positive(t, "viscous_number", f.viscous_number);
  read_non_negative(t, "reference_velocity", f.reference_velocity);
  read_non_negative(t, "max_dt", f.max_dt);
  read_choice(t, "turbulence", f.turbulence, {"none", "sps"});
  read_positive(t, "smagorinsky", f.smagorinsky);
  t.read("free_surface", f.free_surface);
  read_non_negative(t, "surface_threshold", f.surface_threshold);
  read_non_negative(t, "surface_full", f.surface_full);
  read_choice(t, "surface_pressure", f.surface_pressure, {"extrapolated", "zero"});
  read_choice(t, "escape", f.escape, {"remove", "stop"});
  // Judged with the defaults in place of zeros, so that a threshold above the default full value is caught.
  const int d = t.ctx().dimension;
  const double threshold = f.surface_threshold > 0.0 ? f.surface_threshold : default_surface_threshold(d);
  const double full = f.surface_full > 0.0 ? f.surface_full : default_surface_full(d);
  if (f.surface_threshold >= 0.0 && f.surface_full >= 0.0 && !(full > threshold))
    t.problem("surface_full", "must be > surface_threshold (got " + show(full) +
                                  (f.surface_full > 0.0 ? "" : " (default)") + " <= " + show(threshold) +
                                  (f.surface_threshold > 0.0 ? "" : " (default)") + ")");
  t.read("shifting", f.shifting);
  t.read("ppe", f.ppe);
  t.read("wcsph", f.wcsph);
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
      t.problem(key, "hi must be > lo (got [" + show(range[0]) + ", " + show(range[1]) + "])");
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
  if (!(nu > -1.0)) t.problem("poisson_ratio", "must be > -1 (got " + show(nu) + ")");
  if (!(nu < 0.5)) t.problem("poisson_ratio", "must be < 0.5 (got " + show(nu) + ")");
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
    read_choice(t, "plane", m.plane, {"strain", "stress"});
  } else if (t.has("plane")) {
    t.ignore("plane");
    t.problem("plane", "only used in 2D (dimension = 3)");
  }
}

void read_fields(Table& t, InitialVelocitySpec& v) {
  if (!read_choice(t, "type", v.type, {"none", "uniform", "cantilever_mode"})) {
    t.ignore_rest();
    return;
  }
  if (v.type == "uniform") {
    t.read("value", v.value, Need::required);
  } else if (v.type == "cantilever_mode") {
    read_positive(t, "kL", v.kL);
    t.read("tip_velocity", v.tip_velocity, Need::required);
    read_positive(t, "length", v.length, Need::required);
    t.read("root", v.root);
    read_direction(t, "axis", v.axis);
    read_direction(t, "direction", v.direction);
  }
}

void read_fields(Table& t, MotionSpec& m) {
  if (!read_choice(t, "type", m.type, {"none", "constant_velocity", "translation", "rotation"}, Need::required)) {
    t.ignore_rest();
    return;
  }
  if (m.type == "none") return;
  if (m.type == "constant_velocity") {
    t.read("velocity", m.velocity, Need::required);
    return;
  }
  if (m.type == "translation") {
    read_direction(t, "direction", m.direction);
  } else if (t.ctx().dimension != 2) {
    t.problem("type", "\"rotation\" is only for dimension = 2 (dimension = " + std::to_string(t.ctx().dimension) + ")");
    t.ignore_rest();
    return;
  } else {
    t.read("pivot", m.pivot, Need::required);
  }
  if (!read_choice(t, "profile", m.profile, {"polynomial", "sine", "csv"}, Need::required)) {
    t.ignore_rest();
    return;
  }
  if (m.profile == "polynomial") {
    if (t.read("coefficients", m.coefficients, Need::required) && m.coefficients.empty())
      t.problem("coefficients", "must not be empty");
    read_non_negative(t, "until", m.until);
  } else if (m.profile == "sine") {
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
  const std::string kind_is = "kind = " + quote(kind_name(b.kind));
  // Structures need an elastic material and fluids a newtonian one (check_lists); walls may name one.
  t.read("material", b.material, wall ? Need::optional : Need::required);
  t.read("shape", b.shape, Need::required);
  if (b.kind == ParticleKind::structure) {
    t.read("clamps", b.clamps);
    if (t.read("refinement", b.refinement) && !(b.refinement >= 1.0 && b.refinement <= 16.0))
      t.problem("refinement", "must be in [1, 16]: the structure's spacing is dx / refinement, finer than the "
                              "water's or equal (got " + show(b.refinement) + ")");
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
        t.problem("lattice_offset", "every component must be in [0, 1), in units of the body's spacing (got " + show(b.lattice_offset[k]) +
                                        " in component " + std::to_string(k) + ")");
        break;
      }
  if (wall) {
    reject(t, "initial_velocity", "not for kind = \"wall\" (use motion)");
  } else if (t.read("initial_velocity", b.initial_velocity) && b.kind == ParticleKind::fluid &&
             b.initial_velocity.type == "cantilever_mode") {
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
  if (!read_choice(t, "type", l.type, {"edge", "traction", "point", "body"}, Need::required)) {
    t.ignore_rest();
    return;
  }
  t.read("body", l.body, Need::required);
  if (l.type == "edge") {
    t.read("region", l.region, Need::required);
    t.read("force", l.force, Need::required);
  } else if (l.type == "traction") {
    t.read("region", l.region, Need::required);
    t.read("traction", l.traction, Need::required);
  } else if (l.type == "point") {
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
    t.problem("name", "must match [A-Za-z0-9_]+ (got " + quote(p.name) + ")");
  read_choice(t, "type", p.type, {"displacement", "pressure", "velocity", "front", "max_speed"});
  t.read("point", p.point, p.type == "max_speed" ? Need::optional : Need::required);
}

void read_dimension(Table& t, CaseSpec& c) {
  std::int64_t dimension = c.dimension;
  if (!t.read("dimension", dimension)) return;
  if (dimension != 2 && dimension != 3) {
    t.problem("dimension", "must be 2 or 3 (got " + std::to_string(dimension) + ")");
    return;
  }
  c.dimension = t.ctx().dimension = static_cast<int>(dimension);
}

void read_fields(Table& t, CaseSpec& c) {
  if (t.read("name", c.name) && c.name.empty()) t.problem("name", "must not be empty");
  read_dimension(t, c);  // first: the shapes and vectors below depend on it
  read_positive(t, "dx", c.dx, Need::required);
  read_positive(t, "end_time", c.end_time, Need::required);
  t.read("gravity", c.gravity);
  t.read("kernel", c.kernel);
  t.read("structure", c.structure);
  t.read("fluid", c.fluid);
  t.read("coupling", c.coupling);
  t.read("periodic", c.periodic);
  t.read("output", c.output);
  t.read("stages", c.stages);
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
                  "duplicate name " + quote(items[i].name) + " (also " + index_path(list, it->second) + ")");
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
    if (!item.name.empty()) known.push_back(quote(item.name));
  }
  ctx.problem(path, "no " + what + " named " + quote(name) +
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
      ctx.problem(path, "material " + quote(m.name) + " has model = " + quote(m.model) + ", but a " +
                            kind_name(b.kind) + " body needs model = " + quote(needed));
    return;  // a duplicate name is reported already
  }
}

// The first body of `kind` (its path and name, for messages), or "" if there is none.
std::string first_body(const std::vector<BodySpec>& bodies, ParticleKind kind) {
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].kind == kind) return index_path("bodies", i) + " " + quote(bodies[i].name);
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
    const std::string& type = c.probes[i].type;
    const bool structural = type == "displacement";
    if (structural ? c.stages.structure : c.stages.fluid) continue;
    ctx.problem(index_path("probes", i) + ".type",
                quote(type) + " probes need stages." + (structural ? "structure" : "fluid") + " = true");
  }
}

// The rows "time, value" of a motion file: numbers separated by commas, tabs, semicolons or spaces;
// blank lines and lines starting with '#' are skipped, and so is a first line that is not numeric (a
// header). Returns false, with the problem in ctx under `path`, for a file that cannot serve.
bool read_motion_rows(const std::string& file, const std::string& path, Context& ctx, MotionSpec& m) {
  std::ifstream in(file);
  if (!in) {
    ctx.problem(path, "cannot open " + quote(file));
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
      ctx.problem(path, quote(file) + " line " + std::to_string(line_number) +
                            ": expected two numbers, time and value (got " + quote(trim(line)) + ")");
      return false;
    }
    if (!m.times.empty() && !(numbers[0] > m.times.back())) {
      ctx.problem(path, quote(file) + " line " + std::to_string(line_number) + ": the rows must be sorted by time, " +
                            "strictly increasing (t = " + show(numbers[0]) + " follows t = " + show(m.times.back()) +
                            ")");
      return false;
    }
    m.times.push_back(numbers[0]);
    m.values.push_back(numbers[1]);
  }
  if (m.times.size() >= 2) return true;
  ctx.problem(path, quote(file) + ": needs at least two rows (got " + std::to_string(m.times.size()) + ")");
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
    if (b.kind == ParticleKind::structure && b.motion.type != "none" && b.clamps.empty())
      ctx.problem(path, "moves the clamped particles of a structure, and this body has no clamps");
    MotionSpec& m = b.motion;
    if ((m.type != "translation" && m.type != "rotation") || m.profile != "csv" || m.file.empty()) continue;
    std::filesystem::path file(m.file);
    if (file.is_relative()) file = folder / file;
    m.file = std::filesystem::absolute(file).lexically_normal().string();
    if (!read_motion_rows(m.file, path + ".file", ctx, m)) continue;
    if (m.times.back() < c.end_time)
      ctx.problem(path + ".file", quote(m.file) + " ends at t = " + show(m.times.back()) +
                                      " s, before end_time = " + show(c.end_time) + " s");
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
      if (!node) return walked + ": no element with index or name " + quote(segment);
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

// A TOML float: the shortest round-trip text, with ".0" where it would read as an integer.
std::string toml_float(double x) {
  std::string text = show(x);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return text;
}

std::string toml_bool(bool b) { return b ? "true" : "false"; }

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
    return inline_table({{"type", quote(s.type)},
                         {"center", toml_vector(s.center, dimension)},
                         {"radius", toml_float(s.radius)}});
  return inline_table({{"type", quote(s.type)},
                       {"min", toml_vector(s.min, dimension)},
                       {"max", toml_vector(s.max, dimension)}});
}

std::string toml_velocity(const InitialVelocitySpec& v, int dimension) {
  if (v.type == "uniform")
    return inline_table({{"type", quote(v.type)}, {"value", toml_vector(v.value, dimension)}});
  if (v.type == "cantilever_mode")
    return inline_table({{"type", quote(v.type)},
                         {"kL", toml_float(v.kL)},
                         {"tip_velocity", toml_float(v.tip_velocity)},
                         {"length", toml_float(v.length)},
                         {"root", toml_vector(v.root, dimension)},
                         {"axis", toml_vector(v.axis, dimension)},
                         {"direction", toml_vector(v.direction, dimension)}});
  return inline_table({{"type", quote(v.type)}});
}

std::string toml_motion(const MotionSpec& m, int dimension) {
  std::vector<std::pair<std::string, std::string>> entries{{"type", quote(m.type)}};
  if (m.type == "constant_velocity") entries.emplace_back("velocity", toml_vector(m.velocity, dimension));
  if (m.type == "translation") entries.emplace_back("direction", toml_vector(m.direction, dimension));
  if (m.type == "rotation") entries.emplace_back("pivot", toml_vector(m.pivot, dimension));
  if (m.type == "translation" || m.type == "rotation") {
    entries.emplace_back("profile", quote(m.profile));
    if (m.profile == "polynomial") {
      std::vector<std::string> items;
      for (double c : m.coefficients) items.push_back(toml_float(c));
      entries.emplace_back("coefficients", "[" + join(items, ", ") + "]");
      entries.emplace_back("until", toml_float(m.until));
    } else if (m.profile == "sine") {
      entries.emplace_back("amplitude", toml_float(m.amplitude));
      entries.emplace_back("period", toml_float(m.period));
      entries.emplace_back("phase", toml_float(m.phase));
    } else {
      entries.emplace_back("file", quote(m.file));
    }
  }
  return inline_table(entries);
}

void write_material(std::ostream& out, const MaterialSpec& m, int dimension) {
  out << "\n[[materials]]\n"
      << "name = " << quote(m.name) << "\n"
      << "model = " << quote(m.model) << "\n"
      << "density = " << toml_float(m.density) << "\n";
  if (m.model == "newtonian") {
    out << "viscosity = " << toml_float(m.viscosity) << "\n";
    return;
  }
  out << "youngs_modulus = " << toml_float(m.youngs_modulus) << "\n"
      << "poisson_ratio = " << toml_float(m.poisson_ratio) << "\n";
  if (dimension == 2) out << "plane = " << quote(m.plane) << "\n";
}

void write_body(std::ostream& out, const BodySpec& b, int dimension) {
  std::vector<std::string> clamps;
  for (const auto& clamp : b.clamps) clamps.push_back(toml_shape(clamp, dimension));
  out << "\n[[bodies]]\n"
      << "name = " << quote(b.name) << "\n"
      << "kind = " << quote(kind_name(b.kind)) << "\n";
  if (!b.material.empty()) out << "material = " << quote(b.material) << "\n";
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
      << "type = " << quote(l.type) << "\n"
      << "body = " << quote(l.body) << "\n";
  if (l.type == "edge" || l.type == "traction") out << "region = " << toml_shape(l.region, dimension) << "\n";
  if (l.type == "point") out << "point = " << toml_vector(l.region.center, dimension) << "\n";
  if (l.type == "body")
    out << "acceleration = " << toml_vector(l.acceleration, dimension) << "\n";
  else if (l.type == "traction")
    out << "traction = " << toml_vector(l.traction, dimension) << "\n";
  else
    out << "force = " << toml_vector(l.force, dimension) << "\n";
  out << "ramp_time = " << toml_float(l.ramp_time) << "\n";
}

void write_probe(std::ostream& out, const ProbeSpec& p, int dimension) {
  out << "\n[[probes]]\n"
      << "name = " << quote(p.name) << "\n"
      << "type = " << quote(p.type) << "\n"
      << "point = " << toml_vector(p.point, dimension) << "\n";
}

void write_fluid(std::ostream& out, const FluidSpec& f) {
  out << "\n[fluid]\n"
      << "model = " << quote(f.model) << "\n"
      << "courant = " << toml_float(f.courant) << "\n"
      << "viscous_number = " << toml_float(f.viscous_number) << "\n"
      << "reference_velocity = " << toml_float(f.reference_velocity) << "\n"
      << "max_dt = " << toml_float(f.max_dt) << "\n"
      << "turbulence = " << quote(f.turbulence) << "\n"
      << "smagorinsky = " << toml_float(f.smagorinsky) << "\n"
      << "free_surface = " << toml_bool(f.free_surface) << "\n"
      << "surface_threshold = " << toml_float(f.surface_threshold) << "\n"
      << "surface_full = " << toml_float(f.surface_full) << "\n"
      << "surface_pressure = " << quote(f.surface_pressure) << "\n"
      << "escape = " << quote(f.escape) << "\n"
      << "\n[fluid.shifting]\n"
      << "type = " << quote(f.shifting.type) << "\n"
      << "coefficient = " << toml_float(f.shifting.coefficient) << "\n"
      << "max_fraction = " << toml_float(f.shifting.max_fraction) << "\n"
      << "taylor_correction = " << toml_bool(f.shifting.taylor_correction) << "\n"
      << "\n[fluid.ppe]\n"
      << "backend = " << quote(f.ppe.backend) << "\n"
      << "method = " << quote(f.ppe.method) << "\n"
      << "preconditioner = " << quote(f.ppe.preconditioner) << "\n"
      << "tolerance = " << toml_float(f.ppe.tolerance) << "\n"
      << "max_iterations = " << f.ppe.max_iterations << "\n"
      << "fallback = " << quote(f.ppe.fallback) << "\n"
      << "preconditioner_reuse = " << f.ppe.preconditioner_reuse << "\n"
      << "\n[fluid.wcsph]\n"
      << "time_stepping = " << quote(f.wcsph.time_stepping) << "\n"
      << "advection_courant = " << toml_float(f.wcsph.advection_courant) << "\n"
      << "acoustic_courant = " << toml_float(f.wcsph.acoustic_courant) << "\n"
      << "sound_speed = " << toml_float(f.wcsph.sound_speed) << "\n"
      << "riemann_limiter = " << toml_float(f.wcsph.riemann_limiter) << "\n";
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
  out << "# The case as run: overrides applied, every default written out.\n"
      << "name = " << quote(c.name) << "\n"
      << "dimension = " << d << "\n"
      << "dx = " << toml_float(c.dx) << "\n"
      << "end_time = " << toml_float(c.end_time) << "\n"
      << "gravity = " << toml_vector(c.gravity, d) << "\n"
      << "\n[kernel]\n"
      << "type = " << quote(c.kernel.type) << "\n"
      << "h_factor = " << toml_float(c.kernel.h_factor) << "\n"
      << "correction = " << toml_bool(c.kernel.correction) << "\n"
      << "\n[structure]\n"
      << "integrator = " << quote(c.structure.integrator) << "\n"
      << "gradient = " << quote(c.structure.gradient) << "\n"
      << "quadrature = " << quote(c.structure.quadrature) << "\n"
      << "courant = " << toml_float(c.structure.courant) << "\n"
      << "damping = " << toml_float(c.structure.damping) << "\n"
      << "hourglass = " << toml_float(c.structure.hourglass) << "\n";
  write_fluid(out, c.fluid);
  out << "\n[coupling]\n"
      << "substeps = " << c.coupling.substeps << "\n"
      << "fsi_shifting = " << toml_bool(c.coupling.fsi_shifting) << "\n"
      << "wall_contact = " << toml_bool(c.coupling.wall_contact) << "\n"
      << "implicit_added_mass = " << toml_bool(c.coupling.implicit_added_mass) << "\n"
      << "interaction_force = " << quote(c.coupling.interaction_force) << "\n"
      << "substep_interaction = " << quote(c.coupling.substep_interaction) << "\n"
      << "tolerance = " << toml_float(c.coupling.tolerance) << "\n"
      << "max_iterations = " << c.coupling.max_iterations << "\n"
      << "first_ppe_tolerance = " << toml_float(c.coupling.first_ppe_tolerance) << "\n"
      << "reuse_steps = " << c.coupling.reuse_steps << "\n";
  write_periodic(out, c.periodic, d);
  out << "\n[output]\n"
      << "interval = " << toml_float(c.output.interval) << "\n"
      << "snapshot_interval = " << toml_float(c.output.snapshot_interval) << "\n"
      << "snapshots = " << toml_bool(c.output.snapshots) << "\n"
      << "\n[stages]\n"
      << "structure = " << toml_bool(c.stages.structure) << "\n"
      << "fluid = " << toml_bool(c.stages.fluid) << "\n";
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
