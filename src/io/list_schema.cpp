// The keys of [[materials]], [[loads]], [[probes]], [[open_boundaries]] and [periodic], declared once (list_schema.hpp;
// the bodies' keys are in list_schema_bodies.cpp, the builder in schema_declaration.hpp), and the lists' entries and
// tables from the schema's writer and generator (schema.hpp).
#include "io/list_schema.hpp"

#include "core/expression.hpp"
#include "io/schema_declaration.hpp"

namespace isph {

namespace {

using namespace schema_declaration;

std::vector<SchemaKey<MaterialSpec>> declare_materials() {
  using M = MaterialSpec;
  std::vector<SchemaKey<M>> keys;
  const auto elastic = [](const M& m, int) { return m.model != MaterialModel::newtonian; };
  const auto not_elastic = [](const M& m, int) { return "only for an elastic model (" + is("model", m.model) + ")"; };
  add(
      keys, "name", [](M & m) -> auto& { return m.name; })
      .required()
      .doc("unique among materials");
  add(
      keys, "model", [](M & m) -> auto& { return m.model; })
      .discriminator()
      .doc(
          R"(for structures, with the small-strain moduli of youngs_modulus and poisson_ratio (structure/elastic_law.hpp): `"saint_venant_kirchhoff"` (the seed's), `"neo_hookean"` (compressible, Bonet & Wood 2008), `"mooney_rivlin"` (compressible, Holzapfel 2000); for fluids: `"newtonian"`)");
  add(
      keys, "density", [](M & m) -> auto& { return m.density; })
      .unit("kg/m³")
      .bounds(positive())
      .required();
  add(
      keys, "poisson_ratio", [](M & m) -> auto& { return m.poisson_ratio; })
      .bounds({-1, 0.5, true, true})
      .required()
      .only(elastic, "elastic models", not_elastic)
      .doc("ν");
  add(
      keys, "youngs_modulus", [](M & m) -> auto& { return m.youngs_modulus; })
      .unit("Pa")
      .bounds(positive())
      .only(elastic, "elastic models", not_elastic)
      .default_text("one of the two")
      .written([](const M& m) { return m.bulk_modulus == 0; })
      .doc("E; give exactly one of youngs_modulus and bulk_modulus");
  add(
      keys, "bulk_modulus", [](M & m) -> auto& { return m.bulk_modulus; })
      .unit("Pa")
      .bounds(positive())
      .only(elastic, "elastic models", not_elastic)
      .default_text("one of the two")
      .written([](const M& m) { return m.bulk_modulus > 0; })
      .doc("K, instead of youngs_modulus: then E = 3K(1 − 2ν)");
  add(
      keys, "plane", [](M & m) -> auto& { return m.plane; })
      .only([](const M& m, int d) { return d == 2 && m.model != MaterialModel::newtonian; }, "elastic models, 2D",
            [](const M& m, int d) {
              return d != 2 ? "only used in 2D (dimension = " + std::to_string(d) + ")"
                            : "only for an elastic model (" + is("model", m.model) + ")";
            })
      .check([](const M& m, int) -> std::string {
        if (m.plane == PlaneCondition::strain || m.model == MaterialModel::saint_venant_kirchhoff) return "";
        return "\"stress\" is only for saint_venant_kirchhoff; the hyperelastic models are plane strain in 2D (" +
               is("model", m.model) + ")";
      })
      .doc("plane strain or plane stress (St. Venant-Kirchhoff only)");
  add(
      keys, "c01_fraction", [](M & m) -> auto& { return m.c01_fraction; })
      .bounds({0, 1, false, true})
      .only([](const M& m, int) { return m.model == MaterialModel::mooney_rivlin; }, "mooney_rivlin",
            [](const M& m, int) { return "only for mooney_rivlin (" + is("model", m.model) + ")"; })
      .doc(
          "c01 / (c10 + c01), with c10 + c01 = mu/2; 0 is a Neo-Hookean shear energy with Mooney-Rivlin's "
          "volumetric one");
  add(
      keys, "viscosity", [](M & m) -> auto& { return m.viscosity; })
      .unit("m²/s")
      .bounds(positive())
      .required()
      .only([](const M& m, int) { return m.model == MaterialModel::newtonian; }, "newtonian",
            [](const M& m, int) { return "only for newtonian (" + is("model", m.model) + ")"; })
      .doc("kinematic viscosity ν");
  return keys;
}

std::vector<SchemaKey<LoadSpec>> declare_loads() {
  using L = LoadSpec;
  std::vector<SchemaKey<L>> keys;
  // Only for loads of these types.
  const auto of = [](std::vector<LoadType> types) { return only_where(&L::type, "type", std::move(types)); };
  add(
      keys, "type", [](L & l) -> auto& { return l.type; })
      .required()
      .discriminator()
      .doc(R"(`"edge"`, `"traction"`, `"point"`, `"body"`)");
  add(
      keys, "body", [](L & l) -> auto& { return l.body; })
      .required()
      .doc("name of a body");
  only(add(
           keys, "region", [](L & l) -> auto& { return l.region; })
           .required()
           .check([](const L& l, int) -> std::string {
             const bool own = l.region.type == ShapeType::wedge || l.region.type == ShapeType::stl;
             return own ? "a load's region is a rectangle, circle, box, sphere or cylinder" : "";
           }),
       of({LoadType::edge, LoadType::traction}))
      .doc(
          "the free particles of the body whose cell touches it (centre within dx/2) are loaded: \"edge\" shares "
          "force equally among them, \"traction\" gives each traction times its cell's face, dx^(D-1)");
  only(add(
           keys, "point", [](L & l) -> auto& { return l.point; })
           .unit("m")
           .required(),
       of({LoadType::point}))
      .doc("the force acts on the particle nearest this point");
  only(add(
           keys, "force", [](L & l) -> auto& { return l.force; })
           .unit("N")
           .required(),
       of({LoadType::edge, LoadType::point}))
      .doc("total force (N per unit depth in 2D)");
  only(add(
           keys, "traction", [](L & l) -> auto& { return l.traction; })
           .unit("Pa")
           .required(),
       of({LoadType::traction}))
      .doc("force per unit area of the loaded face");
  only(add(
           keys, "acceleration", [](L & l) -> auto& { return l.acceleration; })
           .unit("m/s²")
           .required(),
       of({LoadType::body}))
      .doc("applied to every particle of the body");
  add(
      keys, "ramp_time", [](L & l) -> auto& { return l.ramp_time; })
      .unit("s")
      .bounds(non_negative())
      .doc("linear ramp from 0 to full (0: at once)");
  return keys;
}

// Probe names become column names and file names.
bool is_identifier(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

std::vector<SchemaKey<ProbeSpec>> declare_probes() {
  using P = ProbeSpec;
  std::vector<SchemaKey<P>> keys;
  add(
      keys, "name", [](P & p) -> auto& { return p.name; })
      .required()
      .check([](const P& p, int) {
        return is_identifier(p.name) ? "" : "must match [A-Za-z0-9_]+ (got " + quoted(p.name) + ")";
      })
      .doc("unique among probes; a column and file name");
  add(
      keys, "type", [](P & p) -> auto& { return p.type; })
      .doc(
          R"(`"displacement"`, `"structure_pressure"`, `"pressure"`, `"velocity"`, `"front"`, `"max_speed"`, `"water_level"`, `"force"`: see below)");
  add(
      keys, "point", [](P & p) -> auto& { return p.point; })
      .unit("m")
      .required_when([](const P& p) { return p.type != ProbeType::max_speed && p.type != ProbeType::force; },
                     R"(required (except "max_speed" and "force"))")
      .doc("see below");
  const auto force_only = only_where(&P::type, "type", {ProbeType::force});
  only(add(
           keys, "body", [](P & p) -> auto& { return p.body; })
           .required_when([](const P& p) { return p.type == ProbeType::force; }, R"(required for "force")"),
       force_only)
      .doc("name of the wall or structure body the force acts on");
  only(add(
           keys, "terms", [](P & p) -> auto& { return p.terms; }),
       force_only)
      .doc(
          R"(`"pressure"`: the pressure force; `"all"`: also the viscous traction and the impulses of the projection's impermeability condition, the fluid's whole force, as a drag (a structure feels the first, not the second))");
  return keys;
}

std::vector<SchemaKey<OpenBoundarySpec>> declare_open_boundaries() {
  using O = OpenBoundarySpec;
  std::vector<SchemaKey<O>> keys;
  const auto for_type = [](OpenBoundaryType type) { return only_where(&O::type, "type", {type}); };
  add(
      keys, "name", [](O & o) -> auto& { return o.name; })
      .required()
      .doc("unique among open boundaries");
  add(
      keys, "type", [](O & o) -> auto& { return o.type; })
      .required()
      .discriminator()
      .doc(R"(`"inlet"` (a prescribed velocity) or `"outlet"` (a prescribed pressure))");
  add(
      keys, "point", [](O & o) -> auto& { return o.point; })
      .unit("m")
      .required()
      .doc("a point of the boundary's plane, inside the walls' bounding box");
  add(
      keys, "normal", [](O & o) -> auto& { return o.normal; })
      .required()
      .check([](const O& o, int d) -> std::string {
        double n2 = 0;
        for (int k = 0; k < d; ++k) n2 += o.normal[k] * o.normal[k];
        return n2 > 0 ? "" : "must not be zero";
      })
      .doc("the plane's normal, pointing into the fluid (it is normalised); the buffer lies behind the plane");
  add(
      keys, "layers", [](O & o) -> auto& { return o.layers; })
      .bounds(non_negative())
      .default_text("the kernel's support over dx, rounded up, plus one")
      .doc("the buffer's thickness in particle spacings; at least the kernel's support");
  only(add(
           keys, "velocity", [](O & o) -> auto& { return o.velocity; })
           .required()
           .check([](const O& o, int) -> std::string {
             try {
               Expression::parse(o.velocity);
               return "";
             } catch (const ExpressionError& e) {
               return e.what();
             }
           }),
       for_type(OpenBoundaryType::inlet))
      .unit("m/s")
      .doc(
          "the inflow speed along the normal, an expression of x, y, z and t (e.g. "
          "`\"1.5 * 4 * y * (0.41 - y) / 0.41^2\"`; docs/CASES.md lists its operators and functions)");
  only(add(
           keys, "flow_rate", [](O & o) -> auto& { return o.flow_rate; })
           .bounds(non_negative()),
       for_type(OpenBoundaryType::inlet))
      .unit("m²/s (2D), m³/s (3D)")
      .doc("when > 0, the velocity's shape is scaled so that the buffer carries this flow across the plane");
  only(add(
           keys, "ramp_time", [](O & o) -> auto& { return o.ramp_time; })
           .bounds(non_negative()),
       for_type(OpenBoundaryType::inlet))
      .unit("s")
      .doc("the speed grows as (1 − cos(π t / ramp_time)) / 2 until ramp_time (0: at once)");
  only(add(
           keys, "pressure", [](O & o) -> auto& { return o.pressure; }),
       for_type(OpenBoundaryType::outlet))
      .unit("Pa")
      .doc("the pressure of the outlet's buffer");
  return keys;
}

std::vector<SchemaKey<PeriodicSpec>> declare_periodic() {
  std::vector<SchemaKey<PeriodicSpec>> keys;
  static const char* const kAxes[] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    auto d = add(
                 keys, kAxes[k], [k](PeriodicSpec & p) -> auto& { return p.range[k]; })
                 .unit("m")
                 .default_text("not periodic")
                 .check([k](const PeriodicSpec& p, int) -> std::string {
                   const auto& r = p.range[k];
                   if (r.size() != 2) return "expected 2 numbers [lo, hi], got " + std::to_string(r.size());
                   if (!(r[1] > r[0]))
                     return "hi must be > lo (got [" + shortest_number(r[0]) + ", " + shortest_number(r[1]) + "])";
                   return "";
                 })
                 .written([k](const PeriodicSpec& p) { return p.axis(k); })
                 .doc("`[lo, hi]` with hi > lo");
    if (k == 2)
      d.only([](const PeriodicSpec&, int dim) { return dim == 3; }, "3D",
             [](const PeriodicSpec&, int dim) { return "only in 3D (dimension = " + std::to_string(dim) + ")"; });
  }
  return keys;
}

}  // namespace

const std::vector<SchemaKey<MaterialSpec>>& material_keys() {
  static const auto keys = declare_materials();
  return keys;
}
const std::vector<SchemaKey<LoadSpec>>& load_keys() {
  static const auto keys = declare_loads();
  return keys;
}
const std::vector<SchemaKey<ProbeSpec>>& probe_keys() {
  static const auto keys = declare_probes();
  return keys;
}
const std::vector<SchemaKey<OpenBoundarySpec>>& open_boundary_keys() {
  static const auto keys = declare_open_boundaries();
  return keys;
}
const std::vector<SchemaKey<PeriodicSpec>>& periodic_keys() {
  static const auto keys = declare_periodic();
  return keys;
}

std::vector<std::pair<std::string, std::string>> material_entries(const MaterialSpec& m, int d) {
  return entries(m, material_keys(), d);
}
std::vector<std::pair<std::string, std::string>> body_entries(const BodySpec& b, int d) {
  return entries(b, body_keys(), d);
}
std::vector<std::pair<std::string, std::string>> load_entries(const LoadSpec& l, int d) {
  return entries(l, load_keys(), d);
}
std::vector<std::pair<std::string, std::string>> probe_entries(const ProbeSpec& p, int d) {
  return entries(p, probe_keys(), d);
}
std::vector<std::pair<std::string, std::string>> open_boundary_entries(const OpenBoundarySpec& o, int d) {
  return entries(o, open_boundary_keys(), d);
}
std::vector<std::pair<std::string, std::string>> periodic_entries(const PeriodicSpec& p, int d) {
  return entries(p, periodic_keys(), d);
}

const std::vector<std::string>& list_tables() {
  static const std::vector<std::string> tables = {
      "materials", "bodies", "shape", "initial_velocity", "motion", "loads", "probes", "open_boundaries", "periodic"};
  return tables;
}

std::string list_key_reference(const std::string& table) {
  if (table == "materials") return reference(material_keys(), true);
  if (table == "bodies") return reference(body_keys(), true);
  if (table == "shape") return reference(shape_keys(), true);
  if (table == "initial_velocity") return reference(initial_velocity_keys(), true);
  if (table == "motion") return reference(motion_keys(), true);
  if (table == "loads") return reference(load_keys(), true);
  if (table == "probes") return reference(probe_keys(), true);
  if (table == "open_boundaries") return reference(open_boundary_keys(), true);
  if (table == "periodic") return reference(periodic_keys(), true);
  return "";
}

}  // namespace isph