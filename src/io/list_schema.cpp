#include "io/list_schema.hpp"

#include <algorithm>
#include <type_traits>

#include "io/stl_mesh.hpp"

namespace isph {

namespace {

using Vec3 = std::array<double, 3>;

KeyBounds positive() { return {0, KeyBounds{}.hi, true, true}; }
KeyBounds non_negative() { return {0}; }

std::string quoted(const std::string& name) { return toml_string(name); }

// The shape types of a dimension, in the enum's order: the planar ones in 2D, the others in 3D.
std::vector<std::string> shape_types(int dimension) {
  std::vector<std::string> names;
  for (const auto& entry : enum_names(ShapeType{}))
    if (is_planar(entry.value) == (dimension == 2)) names.emplace_back(entry.name);
  return names;
}

// `kind = "fluid"`: an element's own value of a choice, for the messages.
template <class E>
std::string is(const std::string& key, E value) {
  return key + " = " + quoted(std::string(name_of(value)));
}

template <class Item>
class Declaration {
 public:
  explicit Declaration(ListKey<Item>& key) : key_(key) {}
  Declaration& unit(std::string u) { return key_.unit = std::move(u), *this; }
  Declaration& bounds(KeyBounds b) { return key_.bounds = b, *this; }
  Declaration& choices_in(std::function<std::vector<std::string>(int)> c) {
    return key_.choices_in = std::move(c), *this;
  }
  Declaration& preset(std::function<void(Item&, int)> p) { return key_.preset = std::move(p), *this; }
  Declaration& direction() { return key_.direction = true, *this; }
  Declaration& discriminator() { return key_.discriminator = true, *this; }
  Declaration& required() {
    key_.required = [](const Item&) { return true; };
    return *this;
  }
  Declaration& required_when(std::function<bool(const Item&)> when, std::string text) {
    key_.required = std::move(when);
    key_.default_text = std::move(text);
    return *this;
  }
  // Allowed only for the elements `when` admits; `not_for` says why for another (naming its value).
  Declaration& only(std::function<bool(const Item&, int)> when, std::string for_text,
                    std::function<std::string(const Item&, int)> not_for) {
    key_.applies = std::move(when);
    key_.for_text = std::move(for_text);
    key_.not_for = std::move(not_for);
    return *this;
  }
  Declaration& default_text(std::string text) { return key_.default_text = std::move(text), *this; }
  Declaration& check(std::function<std::string(const Item&, int)> c) { return key_.check = std::move(c), *this; }
  Declaration& written(std::function<bool(const Item&)> w) { return key_.written = std::move(w), *this; }
  Declaration& doc(std::string d) { return key_.doc = std::move(d), *this; }

 private:
  ListKey<Item>& key_;
};

template <class T>
constexpr const char* type_text() {
  if constexpr (std::is_same_v<T, double>) return "float";
  if constexpr (std::is_same_v<T, std::string>) return "string";
  if constexpr (std::is_same_v<T, Vec3>) return "vector";
  if constexpr (std::is_same_v<T, std::vector<double>>) return "array of floats";
  if constexpr (std::is_same_v<T, Shape>) return "shape";
  if constexpr (std::is_same_v<T, std::vector<Shape>>) return "array of shapes";
  if constexpr (std::is_same_v<T, MotionSpec>) return "inline table (motion)";
  if constexpr (std::is_same_v<T, InitialVelocitySpec>) return "inline table (initial_velocity)";
  return "";
}

// A key of an element: its type follows from the member `ref` returns (an enum's makes a choice key).
template <class Item, class Ref>
Declaration<Item> add(std::vector<ListKey<Item>>& keys, std::string name, Ref ref) {
  using T = std::remove_cvref_t<decltype(ref(std::declval<Item&>()))>;
  ListKey<Item>& k = keys.emplace_back();
  k.name = std::move(name);
  if constexpr (std::is_enum_v<T>) {
    k.type = "string";
    for (const auto& entry : enum_names(T{})) k.choices.emplace_back(entry.name);
    k.get_name = [ref](const Item& item) { return std::string(name_of(ref(const_cast<Item&>(item)))); };
    k.set_name = [ref](Item& item, const std::string& name) { ref(item) = *enum_from_name<T>(name); };
  } else {
    k.type = type_text<T>();
    k.field = [ref](Item& item) -> FieldRef { return &ref(item); };
  }
  return Declaration<Item>(k);
}

std::vector<ListKey<MaterialSpec>> declare_materials() {
  using M = MaterialSpec;
  std::vector<ListKey<M>> keys;
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

std::vector<ListKey<Shape>> declare_shapes() {
  std::vector<ListKey<Shape>> keys;
  const auto box = [](const Shape& s, int) { return s.type == ShapeType::rectangle || s.type == ShapeType::box; };
  const auto ball = [](const Shape& s, int) { return is_ball(s.type); };
  const auto wedge = [](const Shape& s, int) { return s.type == ShapeType::wedge; };
  const auto not_box = [](const Shape& s, int) {
    return "only for type = \"rectangle\" or \"box\" (" + is("type", s.type) + ")";
  };
  const auto not_ball = [](const Shape& s, int) {
    return "only for type = \"circle\" or \"sphere\" (" + is("type", s.type) + ")";
  };
  const auto not_wedge = [](const Shape& s, int) { return "only for type = \"wedge\" (" + is("type", s.type) + ")"; };
  const auto cylinder = [](const Shape& s, int) { return s.type == ShapeType::cylinder; };
  const auto not_cylinder = [](const Shape& s, int) {
    return "only for type = \"cylinder\" (" + is("type", s.type) + ")";
  };
  const auto stl = [](const Shape& s, int) { return s.type == ShapeType::stl; };
  const auto not_stl = [](const Shape& s, int) { return "only for type = \"stl\" (" + is("type", s.type) + ")"; };
  add(
      keys, "type", [](Shape & s) -> auto& { return s.type; })
      .required()
      .discriminator()
      .choices_in(shape_types)
      .check([](const Shape& s, int d) -> std::string {
        if (is_planar(s.type) != (d == 2))
          return quoted(std::string(name_of(s.type))) + " is a " + (d == 2 ? "3D" : "2D") +
                 " shape, but dimension = " + std::to_string(d) + "; " + one_of(shape_types(d));
        if (s.type == ShapeType::stl && !stl_available())
          return "\"stl\" needs CGAL, and this build has none: apt-get install libcgal-dev, then configure and "
                 "build again";
        return "";
      })
      .doc(
          R"(2D: `"rectangle"`, `"circle"`, `"wedge"`; 3D: `"box"`, `"sphere"`, `"cylinder"`, `"stl"` (a closed triangle mesh from a file; needs a build with CGAL))");
  add(
      keys, "min", [](Shape & s) -> auto& { return s.min; })
      .unit("m")
      .required()
      .only(box, "rectangle, box", not_box)
      .doc("the lower corner");
  add(
      keys, "max", [](Shape & s) -> auto& { return s.max; })
      .unit("m")
      .required()
      .only(box, "rectangle, box", not_box)
      .doc("the upper corner, > min in every component");
  add(
      keys, "center", [](Shape & s) -> auto& { return s.center; })
      .unit("m")
      .required()
      .only(ball, "circle, sphere", not_ball);
  add(
      keys, "radius", [](Shape & s) -> auto& { return s.radius; })
      .unit("m")
      .bounds(positive())
      .required()
      .only([](const Shape& s, int) { return is_ball(s.type) || s.type == ShapeType::cylinder; },
            "circle, sphere, cylinder",
            [](const Shape& s, int) {
              return "only for type = \"circle\", \"sphere\" or \"cylinder\" (" + is("type", s.type) + ")";
            });
  add(
      keys, "base", [](Shape & s) -> auto& { return s.base; })
      .unit("m")
      .required()
      .only(cylinder, "cylinder", not_cylinder)
      .doc("the centre of one end");
  add(
      keys, "axis", [](Shape & s) -> auto& { return s.axis; })
      .unit("m")
      .required()
      .only(cylinder, "cylinder", not_cylinder)
      .check([](const Shape& s, int) -> std::string {
        return s.axis == Vec3{} ? "must not be the zero vector (its length is the cylinder's length)" : "";
      })
      .doc("from the centre of the base to the centre of the other end, any direction; its length is the length");
  add(
      keys, "file", [](Shape & s) -> auto& { return s.file; })
      .required()
      .only(stl, "stl", not_stl)
      .doc(
          "an STL file, ASCII or binary, relative to the case file's folder (the resolved case gives the absolute "
          "path); its triangles must close a surface (watertight). A particle is inside when its lattice point "
          "is inside the surface or on it");
  add(
      keys, "scale", [](Shape & s) -> auto& { return s.scale; })
      .bounds(positive())
      .only(stl, "stl", not_stl)
      .doc("each vertex v becomes scale v + translate: STL has no units, and scale = 0.001 reads millimetres");
  add(
      keys, "translate", [](Shape & s) -> auto& { return s.translate; })
      .unit("m")
      .only(stl, "stl", not_stl)
      .default_text("`[0.0, 0.0, 0.0]`")
      .doc("added to every vertex after scaling");
  add(
      keys, "apex", [](Shape & s) -> auto& { return s.apex; })
      .unit("m")
      .required()
      .only(wedge, "wedge", not_wedge)
      .doc("the keel: the lowest point of the wedge's outer face");
  add(
      keys, "half_breadth", [](Shape & s) -> auto& { return s.half_breadth; })
      .unit("m")
      .bounds(positive())
      .required()
      .only(wedge, "wedge", not_wedge)
      .doc("the horizontal distance from the keel to each chine");
  add(
      keys, "deadrise", [](Shape & s) -> auto& { return s.deadrise; })
      .unit("°")
      .bounds({0.0, 60.0, false, true})
      .required()
      .only(wedge, "wedge", not_wedge)
      .doc("each panel's angle to the horizontal");
  add(
      keys, "thickness", [](Shape & s) -> auto& { return s.thickness; })
      .unit("m")
      .bounds(positive())
      .required()
      .only(wedge, "wedge", not_wedge)
      .doc("each panel's thickness, normal to the panel");
  return keys;
}

std::vector<ListKey<InitialVelocitySpec>> declare_initial_velocities() {
  using V = InitialVelocitySpec;
  std::vector<ListKey<V>> keys;
  const auto uniform = [](const V& v, int) { return v.type == InitialVelocityType::uniform; };
  const auto mode = [](const V& v, int) { return v.type == InitialVelocityType::cantilever_mode; };
  const auto not_mode = [](const V& v, int) {
    return "only for type = \"cantilever_mode\" (" + is("type", v.type) + ")";
  };
  add(
      keys, "type", [](V & v) -> auto& { return v.type; })
      .discriminator()
      .doc(
          R"(`"none"`, `"uniform"`, `"cantilever_mode"`: the first bending mode of a clamped-free beam, v = tip_velocity · f(s)/f(length) along `direction`, s the distance from `root` along `axis`, f(s) = (cos kL + cosh kL)(cosh ks − cos ks) + (sin kL − sinh kL)(sinh ks − sin ks), k = kL/length)");
  add(
      keys, "value", [](V & v) -> auto& { return v.value; })
      .unit("m/s")
      .required()
      .only(uniform, "uniform",
            [](const V& v, int) { return "only for type = \"uniform\" (" + is("type", v.type) + ")"; });
  add(
      keys, "tip_velocity", [](V & v) -> auto& { return v.tip_velocity; })
      .unit("m/s")
      .required()
      .only(mode, "cantilever_mode", not_mode);
  add(
      keys, "length", [](V & v) -> auto& { return v.length; })
      .unit("m")
      .bounds(positive())
      .required()
      .only(mode, "cantilever_mode", not_mode);
  add(
      keys, "kL", [](V & v) -> auto& { return v.kL; })
      .bounds(positive())
      .only(mode, "cantilever_mode", not_mode);
  add(
      keys, "root", [](V & v) -> auto& { return v.root; })
      .unit("m")
      .only(mode, "cantilever_mode", not_mode)
      .doc("a point on the clamped end");
  add(
      keys, "axis", [](V & v) -> auto& { return v.axis; })
      .direction()
      .only(mode, "cantilever_mode", not_mode)
      .doc("the beam's axis, normalized");
  add(
      keys, "direction", [](V & v) -> auto& { return v.direction; })
      .direction()
      .only(mode, "cantilever_mode", not_mode)
      .doc("the velocity's direction, normalized");
  return keys;
}

std::vector<ListKey<MotionSpec>> declare_motions() {
  using M = MotionSpec;
  std::vector<ListKey<M>> keys;
  const auto profiled = [](const M& m, int) {
    return m.type == MotionType::translation || m.type == MotionType::rotation;
  };
  const auto law = [profiled](MotionLaw l) {
    return [profiled, l](const M& m, int d) { return profiled(m, d) && m.profile == l; };
  };
  const auto not_law = [](const char* name) {
    return [name](const M& m, int) {
      return std::string("only for profile = \"") + name + "\" (" +
             (m.type == MotionType::translation || m.type == MotionType::rotation ? is("profile", m.profile)
                                                                                  : is("type", m.type)) +
             ")";
    };
  };
  add(
      keys, "type", [](M & m) -> auto& { return m.type; })
      .required()
      .discriminator()
      .check([](const M& m, int d) -> std::string {
        if (m.type != MotionType::rotation || d == 2) return "";
        return "\"rotation\" is only for dimension = 2 (dimension = " + std::to_string(d) + ")";
      })
      .doc(
          R"(`"none"`; `"constant_velocity"`: x = X + velocity t; `"translation"`: x = X + (s(t) − s(0)) direction, s in m; `"rotation"` (2D): x = pivot + R(θ)(X − pivot), θ = s(t) − s(0) in degrees, counter-clockwise)");
  add(
      keys, "velocity", [](M & m) -> auto& { return m.velocity; })
      .unit("m/s")
      .required()
      .only([](const M& m, int) { return m.type == MotionType::constant_velocity; }, "constant_velocity",
            [](const M& m, int) { return "only for type = \"constant_velocity\" (" + is("type", m.type) + ")"; });
  add(
      keys, "direction", [](M & m) -> auto& { return m.direction; })
      .direction()
      .only([](const M& m, int) { return m.type == MotionType::translation; }, "translation",
            [](const M& m, int) { return "only for type = \"translation\" (" + is("type", m.type) + ")"; })
      .doc("normalized");
  add(
      keys, "pivot", [](M & m) -> auto& { return m.pivot; })
      .unit("m")
      .required()
      .only([](const M& m, int) { return m.type == MotionType::rotation; }, "rotation",
            [](const M& m, int) { return "only for type = \"rotation\" (" + is("type", m.type) + ")"; });
  add(
      keys, "profile", [](M & m) -> auto& { return m.profile; })
      .required()
      .discriminator()
      .only(profiled, "translation, rotation",
            [](const M& m, int) {
              return "only for type = \"translation\" or \"rotation\" (" + is("type", m.type) + ")";
            })
      .doc(R"(s(t): `"polynomial"`, `"sine"`, `"csv"` (a natural cubic spline through a file's rows `time, s`))");
  add(
      keys, "coefficients", [](M & m) -> auto& { return m.coefficients; })
      .required()
      .only(law(MotionLaw::polynomial), "polynomial", not_law("polynomial"))
      .check([](const M& m, int) { return m.coefficients.empty() ? "must not be empty" : ""; })
      .doc("s(t) = Σ_k coefficients[k] t^k");
  add(
      keys, "until", [](M & m) -> auto& { return m.until; })
      .unit("s")
      .bounds(non_negative())
      .only(law(MotionLaw::polynomial), "polynomial", not_law("polynomial"))
      .doc("after t = until (> 0) s holds s(until)");
  add(
      keys, "amplitude", [](M & m) -> auto& { return m.amplitude; })
      .required()
      .only(law(MotionLaw::sine), "sine", not_law("sine"))
      .doc("s(t) = amplitude sin(2π t/period + phase)");
  add(
      keys, "period", [](M & m) -> auto& { return m.period; })
      .unit("s")
      .bounds(positive())
      .required()
      .only(law(MotionLaw::sine), "sine", not_law("sine"));
  add(
      keys, "phase", [](M & m) -> auto& { return m.phase; })
      .unit("rad")
      .only(law(MotionLaw::sine), "sine", not_law("sine"));
  add(
      keys, "file", [](M & m) -> auto& { return m.file; })
      .required()
      .only(law(MotionLaw::csv), "csv", not_law("csv"))
      .doc("rows `time, s`, relative to the case file's folder (the resolved case gives the absolute path)");
  return keys;
}

std::vector<ListKey<BodySpec>> declare_bodies() {
  using B = BodySpec;
  std::vector<ListKey<B>> keys;
  const auto structure = [](const B& b, int) { return b.kind == ParticleKind::structure; };
  const auto not_structure_spacing = [](const B& b, int) {
    return "only for kind = \"structure\"; fluid and walls take the case's dx (" + is("kind", b.kind) + ")";
  };
  add(
      keys, "name", [](B & b) -> auto& { return b.name; })
      .required()
      .doc("unique among bodies");
  add(
      keys, "kind", [](B & b) -> auto& { return b.kind; });
  add(
      keys, "material", [](B & b) -> auto& { return b.material; })
      .required_when([](const B& b) { return b.kind != ParticleKind::wall; }, "required for structures and fluids")
      .written([](const B& b) { return !b.material.empty(); })
      .doc(
          "name of a material: saint_venant_kirchhoff for a structure, newtonian for a fluid; optional "
          "(unused) for walls");
  const auto own_lattice = [](const B& b, int) { return b.shape.type != ShapeType::wedge; };
  const auto wedge_lattice = [](const B&, int) {
    return std::string("not for a wedge, which is filled on its own lattice (docs/CASES.md, shapes)");
  };
  add(
      keys, "shape", [](B & b) -> auto& { return b.shape; })
      .required()
      .check([](const B& b, int) -> std::string {
        if (b.shape.type != ShapeType::wedge || b.kind == ParticleKind::structure) return "";
        return "a wedge is a structure's shape (" + is("kind", b.kind) + ")";
      })
      .doc("the region filled with particles");
  add(
      keys, "clamps", [](B & b) -> auto& { return b.clamps; })
      .only(structure, "structure",
            [](const B& b, int) { return "only for kind = \"structure\" (" + is("kind", b.kind) + ")"; })
      .doc("particles of the body inside any clamp are fixed");
  add(
      keys, "refinement", [](B & b) -> auto& { return b.refinement; })
      .bounds({1, 16})
      .only(structure, "structure", not_structure_spacing)
      .written([](const B& b) { return b.dx == 0; })
      .doc(
          "the case's dx over the body's particle spacing: a structure finer than the water around it "
          "(multi-resolution: every pair takes the kernel of its coarser particle; docs/VALIDATION.md "
          "section 23). The shipped FSI cases use 2");
  add(
      keys, "dx", [](B & b) -> auto& { return b.dx; })
      .unit("m")
      .bounds(positive())
      .only(structure, "structure", not_structure_spacing)
      .default_text("from `refinement`")
      .written([](const B& b) { return b.dx > 0; })
      .doc(
          "the body's own spacing instead of refinement (giving both is an error, and so is a spacing "
          "coarser than the case's dx)");
  add(
      keys, "lattice_origin", [](B & b) -> auto& { return b.lattice_origin; })
      .unit("m")
      .only(own_lattice, "all but wedges", wedge_lattice)
      .preset([](B& b, int d) { b.lattice_origin = b.shape.bounding_box(d).first; })
      .default_text("the lower corner of the shape's bounding box")
      .doc("particles at origin + (i + offset) s inside the shape, s the body's spacing");
  add(
      keys, "lattice_offset", [](B & b) -> auto& { return b.lattice_offset; })
      .only(own_lattice, "all but wedges", wedge_lattice)
      .check([](const B& b, int d) -> std::string {
        for (int k = 0; k < d; ++k)
          if (!(b.lattice_offset[k] >= 0.0 && b.lattice_offset[k] < 1.0))
            return "every component must be in [0, 1), in units of the body's spacing (got " +
                   shortest_number(b.lattice_offset[k]) + " in component " + std::to_string(k) + ")";
        return "";
      })
      .doc(
          "each component in [0, 1), in units of s: with ½ the shape's faces lie s/2 beyond its outer particles; with "
          "0 on an axis, "
          "particle rows lie on the faces through lattice_origin (a clamp's face, a loaded end: "
          "cases/cantilever.toml). Every particle has the volume s^D either way");
  add(
      keys, "initial_velocity", [](B & b) -> auto& { return b.initial_velocity; })
      .only([](const B& b, int) { return b.kind != ParticleKind::wall; }, "structure, fluid",
            [](const B&, int) { return std::string("not for kind = \"wall\" (use motion)"); })
      .check([](const B& b, int) -> std::string {
        if (b.kind != ParticleKind::fluid || b.initial_velocity.type != InitialVelocityType::cantilever_mode) return "";
        return R"(type "cantilever_mode" is only for kind = "structure"; a fluid takes "none" or "uniform")";
      })
      .default_text(R"(`{ type = "none" }`)")
      .doc("see `initial_velocity` below");
  add(
      keys, "motion", [](B & b) -> auto& { return b.motion; })
      .only([](const B& b, int) { return b.kind != ParticleKind::fluid; }, "wall, structure",
            [](const B& b, int) {
              return "only for kind = \"wall\" or \"structure\" (" + is("kind", b.kind) + "; see initial_velocity)";
            })
      .default_text(R"(`{ type = "none" }`)")
      .doc(
          "walls: their prescribed rigid motion; structures: the motion of their clamped particles (the "
          "clamp moves with the tank it sits in). See `motion` below");
  return keys;
}

std::vector<ListKey<LoadSpec>> declare_loads() {
  using L = LoadSpec;
  std::vector<ListKey<L>> keys;
  // Only for loads of these types.
  const auto of = [](std::vector<LoadType> types) {
    std::string text, message;
    for (std::size_t i = 0; i < types.size(); ++i) {
      text += (i ? ", " : "") + name_of(types[i]);
      message += (i ? " or " : "") + quoted(name_of(types[i]));
    }
    return std::tuple{
        [types](const L& l, int) { return std::find(types.begin(), types.end(), l.type) != types.end(); }, text,
        [message](const L& l, int) { return "only for type = " + message + " (" + is("type", l.type) + ")"; }};
  };
  const auto only = [](Declaration<L> d, auto rule) -> Declaration<L> {
    auto [when, text, why] = rule;
    d.only(when, text, why);
    return d;
  };
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

std::vector<ListKey<ProbeSpec>> declare_probes() {
  using P = ProbeSpec;
  std::vector<ListKey<P>> keys;
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
  add(
      keys, "body", [](P & p) -> auto& { return p.body; })
      .required_when([](const P& p) { return p.type == ProbeType::force; }, R"(required for "force")")
      .only([](const P& p, int) { return p.type == ProbeType::force; }, "force",
            [](const P& p, int) { return "only for type = \"force\" (" + is("type", p.type) + ")"; })
      .doc("name of the wall or structure body the force acts on");
  return keys;
}

std::vector<ListKey<PeriodicSpec>> declare_periodic() {
  std::vector<ListKey<PeriodicSpec>> keys;
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

// ---------------------------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------------------------

std::string inline_table(const std::vector<std::pair<std::string, std::string>>& entries) {
  std::string text = "{ ";
  for (std::size_t i = 0; i < entries.size(); ++i)
    text += (i ? ", " : "") + entries[i].first + " = " + entries[i].second;
  return text + " }";
}

template <class Item>
std::vector<std::pair<std::string, std::string>> entries(const Item& item, const std::vector<ListKey<Item>>& keys,
                                                         int dimension);

std::string value_text(const FieldRef& field, int dimension) {
  struct Text {
    int d;
    std::string operator()(double* x) const { return toml_float(*x); }
    std::string operator()(std::string* s) const { return toml_string(*s); }
    std::string operator()(Vec3* v) const { return toml_value(*v, d); }
    std::string operator()(std::vector<double>* v) const {
      std::string text = "[";
      for (std::size_t i = 0; i < v->size(); ++i) text += (i ? ", " : "") + toml_float((*v)[i]);
      return text + "]";
    }
    std::string operator()(Shape* s) const { return inline_table(entries(*s, shape_keys(), d)); }
    std::string operator()(std::vector<Shape>* shapes) const {
      std::string text = "[";
      for (std::size_t i = 0; i < shapes->size(); ++i) text += (i ? ", " : "") + (*this)(&(*shapes)[i]);
      return text + "]";
    }
    std::string operator()(MotionSpec* m) const { return inline_table(entries(*m, motion_keys(), d)); }
    std::string operator()(InitialVelocitySpec* v) const {
      return inline_table(entries(*v, initial_velocity_keys(), d));
    }
  };
  return std::visit(Text{dimension}, field);
}

template <class Item>
std::string key_text(const ListKey<Item>& key, const Item& item, int dimension) {
  if (key.get_name) return toml_string(key.get_name(item));
  return value_text(key.field(const_cast<Item&>(item)), dimension);  // read only
}

template <class Item>
std::vector<std::pair<std::string, std::string>> entries(const Item& item, const std::vector<ListKey<Item>>& keys,
                                                         int dimension) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& key : keys) {
    if (key.applies && !key.applies(item, dimension)) continue;
    if (key.written && !key.written(item)) continue;
    out.emplace_back(key.name, key_text(key, item, dimension));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// The docs
// ---------------------------------------------------------------------------------------------

std::string cell(std::string text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

template <class Item>
std::string reference(const std::vector<ListKey<Item>>& keys) {
  Item defaults{};
  std::string table = "| Key | Type | For | Default | Allowed / meaning |\n|---|---|---|---|---|\n";
  for (const auto& k : keys) {
    const std::string type = k.type + (k.unit.empty() ? "" : " [" + k.unit + "]");
    std::string shown = k.default_text;
    if (shown.empty()) shown = k.required ? "required" : "`" + key_text(k, defaults, 2) + "`";
    std::string allowed = k.bounds.text(false);
    if (k.direction) allowed = "non-zero";
    const bool named = std::all_of(k.choices.begin(), k.choices.end(), [&](const std::string& choice) {
      return k.doc.find("`\"" + choice + "\"`") != std::string::npos;
    });
    if (!named)
      for (std::size_t i = 0; i < k.choices.size(); ++i) allowed += (i ? ", `" : "`") + toml_string(k.choices[i]) + "`";
    const std::string meaning = allowed.empty() ? k.doc : k.doc.empty() ? allowed : allowed + "; " + k.doc;
    table += "| `" + k.name + "` | " + type + " | " + (k.for_text.empty() ? "all" : k.for_text) + " | " + shown +
             " | " + cell(meaning) + " |\n";
  }
  return table;
}

}  // namespace

const std::vector<ListKey<MaterialSpec>>& material_keys() {
  static const auto keys = declare_materials();
  return keys;
}
const std::vector<ListKey<BodySpec>>& body_keys() {
  static const auto keys = declare_bodies();
  return keys;
}
const std::vector<ListKey<Shape>>& shape_keys() {
  static const auto keys = declare_shapes();
  return keys;
}
const std::vector<ListKey<InitialVelocitySpec>>& initial_velocity_keys() {
  static const auto keys = declare_initial_velocities();
  return keys;
}
const std::vector<ListKey<MotionSpec>>& motion_keys() {
  static const auto keys = declare_motions();
  return keys;
}
const std::vector<ListKey<LoadSpec>>& load_keys() {
  static const auto keys = declare_loads();
  return keys;
}
const std::vector<ListKey<ProbeSpec>>& probe_keys() {
  static const auto keys = declare_probes();
  return keys;
}
const std::vector<ListKey<PeriodicSpec>>& periodic_keys() {
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
std::vector<std::pair<std::string, std::string>> periodic_entries(const PeriodicSpec& p, int d) {
  return entries(p, periodic_keys(), d);
}

const std::vector<std::string>& list_tables() {
  static const std::vector<std::string> tables = {"materials", "bodies", "shape",  "initial_velocity",
                                                  "motion",    "loads",  "probes", "periodic"};
  return tables;
}

std::string list_key_reference(const std::string& table) {
  if (table == "materials") return reference(material_keys());
  if (table == "bodies") return reference(body_keys());
  if (table == "shape") return reference(shape_keys());
  if (table == "initial_velocity") return reference(initial_velocity_keys());
  if (table == "motion") return reference(motion_keys());
  if (table == "loads") return reference(load_keys());
  if (table == "probes") return reference(probe_keys());
  if (table == "periodic") return reference(periodic_keys());
  return "";
}

}  // namespace isph
