// The case loader's checks across the lists of a case, made once every list is read.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "io/case_loading.hpp"
#include "io/case_schema.hpp"
#include "io/list_schema.hpp"
#include "io/stl_mesh.hpp"

namespace isph::case_loading {

namespace {

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
void check_material_model(const BodySpec& b, const std::vector<MaterialSpec>& materials, const std::string& path,
                          Context& ctx) {
  if (b.kind == ParticleKind::wall || ctx.unknown_model.count(b.material)) return;
  const bool fluid = b.kind == ParticleKind::fluid;
  for (const auto& m : materials) {
    if (m.name != b.material) continue;
    if ((m.model == MaterialModel::newtonian) != fluid)
      ctx.problem(path, "material " + toml_string(m.name) + " has model = " + toml_string(name_of(m.model)) +
                            ", but a " + name_of(b.kind) + " body needs " +
                            (fluid ? "model = \"newtonian\"" : "an elastic model"));
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
  if (c.stages.fluid && fluid.empty()) ctx.problem("stages.fluid", "needs at least one body of kind = \"fluid\"");
  if (!c.stages.fluid && !fluid.empty())
    ctx.problem("stages.fluid", "the case has fluid bodies (" + fluid + "); set stages.fluid = true");
  if (c.stages.structure && structure.empty())
    ctx.problem("stages.structure",
                "needs at least one body of kind = \"structure\" (or set stages.fluid = true "
                "for a fluid case)");
  if (!c.stages.structure && !structure.empty())
    ctx.problem("stages.structure", "the case has structure bodies (" + structure + "); set stages.structure = true");
  if (!c.stages.structure && !c.stages.fluid)
    ctx.problem("stages", "nothing to run: set stages.structure or stages.fluid to true");
  for (std::size_t i = 0; i < c.probes.size(); ++i) {
    const std::string type = name_of(c.probes[i].type);
    const ProbeType t = c.probes[i].type;
    const bool needs_structure = t == ProbeType::displacement || t == ProbeType::structure_pressure;
    const bool needs_fluid = t != ProbeType::displacement;
    if (needs_structure && !c.stages.structure)
      ctx.problem(index_path("probes", i) + ".type", toml_string(type) + " probes need stages.structure = true");
    if (needs_fluid && !c.stages.fluid)
      ctx.problem(index_path("probes", i) + ".type", toml_string(type) + " probes need stages.fluid = true");
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

// A mesh whose bounding box holds more lattice points at its body's spacing than a run could hold is in
// other units (STL has none); it is refused here, as filling it would take hours.
void check_mesh_sizes(const CaseSpec& c, Context& ctx) {
  constexpr double kMaxLatticePoints = 1e8;
  for (std::size_t i = 0; i < c.bodies.size(); ++i) {
    const BodySpec& b = c.bodies[i];
    if (b.shape.type != ShapeType::stl || !b.shape.mesh.mesh || !(c.dx > 0)) continue;
    const double s = b.spacing(c.dx);
    const auto [lo, hi] = b.shape.bounding_box(c.dimension);
    double points = 1;
    for (int k = 0; k < c.dimension; ++k) points *= std::ceil((hi[k] - lo[k]) / s);
    if (points <= kMaxLatticePoints) continue;
    char size[160];
    std::snprintf(size, sizeof size, "%g x %g x %g m, %.2g lattice points at the body's spacing of %g m (at most %g)",
                  hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], points, s, kMaxLatticePoints);
    ctx.problem(index_path("bodies", i) + ".shape.scale",
                "the mesh " + toml_string(b.shape.file) + " spans " + size +
                    ": STL has no units, and a file in millimetres needs scale = 0.001 (in centimetres, 0.01)");
  }
}

}  // namespace

void check_lists(CaseSpec& c, Context& ctx) {
  read_motion_files(c, ctx);
  check_mesh_sizes(c, ctx);
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
  for (std::size_t i = 0; i < c.probes.size(); ++i) {
    if (c.probes[i].type != ProbeType::force) continue;
    const std::string path = index_path("probes", i) + ".body";
    check_reference(c.probes[i].body, c.bodies, "body", path, ctx);
    for (const auto& b : c.bodies)
      if (b.name == c.probes[i].body && b.kind == ParticleKind::fluid)
        ctx.problem(path,
                    "a force probe needs a wall or structure body; " + toml_string(b.name) + " is of kind = \"fluid\"");
  }
  check_unique_names(c.open_boundaries, "open_boundaries", ctx);
  for (std::size_t i = 0; i < c.open_boundaries.size(); ++i) {
    if (!c.stages.fluid)
      ctx.problem(index_path("open_boundaries", i), "open boundaries need stages.fluid = true");
    else if (c.fluid.model != FluidMethod::isph)
      ctx.problem(index_path("open_boundaries", i), "open boundaries are for fluid.model = \"isph\" only");
  }
  check_stages(c, ctx);
}

}  // namespace isph::case_loading
