// The keys of [[bodies]] and of the tables inside them (shape, initial_velocity, motion), declared once
// (list_schema.hpp; the machinery: schema_declaration.hpp).
#include "io/schema_declaration.hpp"
#include "io/stl_mesh.hpp"

namespace isph {

namespace {

using namespace schema_declaration;

std::vector<SchemaKey<Shape>> declare_shapes() {
  std::vector<SchemaKey<Shape>> keys;
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

std::vector<SchemaKey<InitialVelocitySpec>> declare_initial_velocities() {
  using V = InitialVelocitySpec;
  std::vector<SchemaKey<V>> keys;
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

std::vector<SchemaKey<MotionSpec>> declare_motions() {
  using M = MotionSpec;
  std::vector<SchemaKey<M>> keys;
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

std::vector<SchemaKey<BodySpec>> declare_bodies() {
  using B = BodySpec;
  std::vector<SchemaKey<B>> keys;
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
  const auto own_lattice = [](const B& b, int) {
    return b.shape.type != ShapeType::wedge && b.lattice == LatticeType::cartesian;
  };
  const auto not_own_lattice = [](const B& b, int) {
    if (b.lattice == LatticeType::rings)
      return std::string("not with lattice = \"rings\", which are centred on the circle");
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
      keys, "holes", [](B & b) -> auto& { return b.holes; })
      .only([](const B& b, int) { return b.kind != ParticleKind::structure; }, "fluid or wall",
            [](const B& b, int) { return "only for kind = \"fluid\" or \"wall\" (" + is("kind", b.kind) + ")"; })
      .doc(
          "shapes the body leaves empty: in a fluid, the obstacles' wall bodies (a cylinder in a channel: "
          "`cases/dfg_cylinder.toml`); in a wall, the slot where a structure is fixed into it (Turek & Hron's "
          "bar in its cylinder: `cases/turek_hron.toml`)");
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
      keys, "lattice", [](B & b) -> auto& { return b.lattice; })
      .check([](const B& b, int d) -> std::string {
        if (b.lattice != LatticeType::rings) return "";
        if (b.kind != ParticleKind::wall) return "\"rings\" is for walls (" + is("kind", b.kind) + ")";
        if (d == 2 && b.shape.type == ShapeType::circle) return "";
        return "\"rings\" fills a circle in 2D (" + is("shape.type", b.shape.type) + ")";
      })
      .doc(
          "\"cartesian\": the lattice below; \"rings\" (a wall's 2D circle): concentric rings s apart, the outer "
          "one s/2 inside the circle, each with round(2 pi r / s) particles, so that a cylinder's surface is smooth "
          "rather than a staircase (`cases/turek_hron.toml`). Each particle's volume is s^2 (its ring's share "
          "differs by at most 0.5 / n)");
  add(
      keys, "lattice_origin", [](B & b) -> auto& { return b.lattice_origin; })
      .unit("m")
      .only(own_lattice, "all but wedges and rings", not_own_lattice)
      .preset([](B& b, int d) { b.lattice_origin = b.shape.bounding_box(d).first; })
      .default_text("the lower corner of the shape's bounding box")
      .doc("particles at origin + (i + offset) s inside the shape, s the body's spacing");
  add(
      keys, "lattice_offset", [](B & b) -> auto& { return b.lattice_offset; })
      .only(own_lattice, "all but wedges and rings", not_own_lattice)
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

}  // namespace

const std::vector<SchemaKey<BodySpec>>& body_keys() {
  static const auto keys = declare_bodies();
  return keys;
}
const std::vector<SchemaKey<Shape>>& shape_keys() {
  static const auto keys = declare_shapes();
  return keys;
}
const std::vector<SchemaKey<InitialVelocitySpec>>& initial_velocity_keys() {
  static const auto keys = declare_initial_velocities();
  return keys;
}
const std::vector<SchemaKey<MotionSpec>>& motion_keys() {
  static const auto keys = declare_motions();
  return keys;
}

}  // namespace isph
