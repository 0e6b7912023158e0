// The fluid part of a scene: the fluid and wall bodies' particles, the structure's as boundaries, and
// the checks and derived settings of the fluid set-up (finish_fluid).
#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/lattice.hpp"
#include "sim/scene_parts.hpp"

namespace isph {

namespace {

// An axis-aligned box that grows to hold the points added.
template <int D>
struct Box {
  Vec<D> lo, hi;
  Box() {
    for (int d = 0; d < D; ++d) lo[d] = std::numeric_limits<Real>::max(), hi[d] = -lo[d];
  }
  void add(const Vec<D>& x) {
    for (int d = 0; d < D; ++d) lo[d] = std::min(lo[d], x[d]), hi[d] = std::max(hi[d], x[d]);
  }
};

// The kernels, periodicity and settings the fluid model reads, from the case.
template <int D>
void configure_fluid(const CaseSpec& spec, const Resolutions& resolutions, FluidSetup<D>& f) {
  f.dx = spec.dx;
  f.kernels = resolutions.kernels<D>(spec.kernel);
  f.fluid_level = resolutions.fluid_level();
  f.kernel_correction = spec.kernel.correction;
  f.period = periodicity<D>(spec.periodic);
  f.gravity = to_vec<D>(spec.gravity);
  f.settings = spec.fluid;
  f.fsi_shifting = spec.coupling.fsi_shifting;
  f.fsi_shifting_law = spec.coupling.fsi_shifting_law;
  f.interaction_force = spec.coupling.interaction_force;
}

// One fluid material: its density and viscosity.
template <int D>
void set_fluid_material(const CaseSpec& spec, const std::string& file, FluidSetup<D>& f,
                        std::vector<std::string>& problems) {
  std::string material;
  for (std::size_t bi = 0; bi < spec.bodies.size(); ++bi) {
    const BodySpec& b = spec.bodies[bi];
    if (b.kind != ParticleKind::fluid) continue;
    if (material.empty())
      material = b.material;
    else if (b.material != material)
      problems.push_back(file + ": bodies[" + std::to_string(bi) +
                         "].material: all fluid bodies must share one material ('" + material + "' and '" + b.material +
                         "')");
  }
  for (const auto& m : spec.materials)
    if (m.name == material) f.density = m.density, f.viscosity = m.viscosity;
}

// Particles on periodic axes must lie inside the period.
template <int D>
void check_periodic_range(const FluidSetup<D>& f, const std::string& file, std::vector<std::string>& problems) {
  const Index n = static_cast<Index>(f.x.size());
  const Periodicity<D>& period = f.period;
  for (int d = 0; d < D; ++d) {
    if (!period.axis[d]) continue;
    for (Index a = 0; a < n; ++a)
      if (f.x[a][d] < period.lo[d] || f.x[a][d] >= period.lo[d] + period.length[d]) {
        problems.push_back(file + ": periodic: a particle at coordinate " + std::to_string(f.x[a][d]) + " on axis " +
                           std::to_string(d) + " lies outside the periodic range; shrink the bodies to it");
        break;
      }
  }
}

// Overlaps: a fluid particle inside a wall or structure body, a wall particle inside a structure.
template <int D>
void check_overlaps(const CaseSpec& spec, const FluidSetup<D>& f, const std::string& file,
                    std::vector<std::string>& problems) {
  const Index n = static_cast<Index>(f.x.size());
  for (std::size_t bi = 0; bi < spec.bodies.size(); ++bi) {
    const BodySpec& b = spec.bodies[bi];
    if (b.kind == ParticleKind::fluid) continue;
    for (const FluidKind other : {FluidKind::fluid, FluidKind::wall}) {
      if (other == FluidKind::wall && b.kind != ParticleKind::structure) continue;
      Index inside = 0;
      for (Index a = 0; a < n; ++a)
        if (f.kind[a] == other && b.shape.contains(to_array(f.x[a]), D)) ++inside;
      if (inside > 0)
        problems.push_back(file + ": bodies[" + std::to_string(bi) + "].shape: " + std::to_string(inside) + " " +
                           (other == FluidKind::fluid ? "fluid" : "wall") + " particles lie inside this " +
                           (b.kind == ParticleKind::wall ? "wall" : "structure") + " body '" + b.name +
                           "' (bodies of different kinds must not overlap)");
    }
  }
}

// Containment: fluid inside the walls' bounding box on every non-periodic axis (open upwards, against
// gravity). Returns the walls' box.
template <int D>
Box<D> check_containment(const FluidSetup<D>& f, Index walls, const std::string& file,
                         std::vector<std::string>& problems) {
  const Index n = static_cast<Index>(f.x.size());
  bool all_periodic = true;
  for (int d = 0; d < D; ++d) all_periodic = all_periodic && f.period.axis[d];
  Box<D> box;
  for (Index a = 0; a < n; ++a)
    if (f.kind[a] == FluidKind::wall) box.add(f.x[a]);
  if (walls == 0 && !all_periodic) {
    problems.push_back(file + ": bodies: the fluid needs wall bodies around it (or periodic axes)");
  } else {
    Index outside = 0;
    for (Index a = 0; a < n; ++a)
      if (f.kind[a] == FluidKind::fluid && outside_open_box(f.x[a], box.lo, box.hi, f.gravity, f.period)) ++outside;
    if (outside > 0)
      problems.push_back(file + ": bodies: " + std::to_string(outside) +
                         " fluid particles lie outside every wall (beyond the walls' bounding box)");
  }
  return box;
}

// Moving walls: where they go and how fast, sampled over the run (for Eq. 49 and the escape box, which
// `box` grows to hold); and how fast the moving clamps of structures go (for Eq. 49: a slamming wedge's
// water is still until it arrives). Returns the fastest boundary speed.
template <int D>
Real boundary_speed(const CaseSpec& spec, const FluidSetup<D>& f, const TlsphSetup<D>& structure, Box<D>& box) {
  constexpr int samples = 200;
  const auto sample_time = [&spec](int k) { return spec.end_time * k / samples; };
  Real speed = 0;
  for (std::size_t a = 0; a < structure.X.size(); ++a) {
    if (!structure.fixed[a] || structure.motion[a] < 0) continue;
    for (int k = 0; k <= samples; ++k) {
      const Vec<D> v = structure.motions[structure.motion[a]].velocity(structure.X[a], sample_time(k));
      speed = std::max(speed, std::sqrt(norm2(v)));
    }
  }
  for (std::size_t a = 0; a < f.x.size(); ++a) {
    if (f.motion[a] < 0) continue;
    const RigidMotion<D>& m = f.motions[f.motion[a]];
    for (int k = 0; k <= samples; ++k) {
      const Real t = sample_time(k);
      box.add(m.position(f.x[a], t));
      speed = std::max(speed, std::sqrt(norm2(m.velocity(f.x[a], t))));
    }
  }
  return speed;
}

// Reference velocity of Eq. 49: free fall over the fluid's height, or the fastest wall or clamp.
template <int D>
void set_reference_velocity(const CaseSpec& spec, Real boundary_speed, const std::string& file, FluidSetup<D>& f,
                            std::vector<std::string>& problems) {
  Real fluid_lo = std::numeric_limits<Real>::max(), fluid_hi = -fluid_lo;
  const Vec<D> g = f.gravity;
  const Real g_norm = std::sqrt(norm2(g));
  for (std::size_t a = 0; a < f.x.size(); ++a) {
    if (f.kind[a] == FluidKind::fluid && g_norm > 0) {
      const Real height = -dot(f.x[a], g) / g_norm;
      fluid_lo = std::min(fluid_lo, height), fluid_hi = std::max(fluid_hi, height);
    }
  }
  const Real fall = g_norm > 0 ? std::sqrt(2 * g_norm * (fluid_hi - fluid_lo + spec.dx)) : 0;
  f.reference_velocity =
      spec.fluid.reference_velocity > 0 ? spec.fluid.reference_velocity : std::max(fall, boundary_speed);
  if (!(f.reference_velocity > 0))
    problems.push_back(file +
                       ": fluid.reference_velocity: no gravity and no moving wall or clamp; give the velocity scale of "
                       "the flow (Eq. 49 needs it)");
}

// Escape box: the box of all particles (and of the moving walls' paths, already in `box`) grown by 2h,
// and upwards (against gravity) by its own size.
template <int D>
void set_escape_box(const FluidSetup<D>& f, Box<D> box, Scene<D>& scene) {
  for (const Vec<D>& x : f.x) box.add(x);
  const Vec<D>& g = f.gravity;
  const Real g_norm = std::sqrt(norm2(g));
  const Vec<D>&lo = box.lo, &hi = box.hi;
  if (g_norm > 0) {
    scene.up = (-1.0 / g_norm) * g;
    scene.rim = -std::numeric_limits<Real>::max();
    for (int corner = 0; corner < (1 << D); ++corner) {  // the box's highest corner
      Vec<D> c;
      for (int d = 0; d < D; ++d) c[d] = (corner >> d) & 1 ? hi[d] : lo[d];
      scene.rim = std::max(scene.rim, dot(c, scene.up));
    }
    // Less one kernel support: a particle that leaves the box sideways within 2h of the walls' top has
    // come over their top corner (the Walhorn obstacle's spray left at 0.16 mm below the top row at
    // 0.649 s); one that leaks through a wall lower down still stops the run.
    scene.rim -= f.fluid_kernel().support();
  }
  const Periodicity<D>& period = f.period;
  for (int d = 0; d < D; ++d) {
    const Real margin = f.fluid_kernel().support();
    scene.domain_lo[d] = period.axis[d] ? -std::numeric_limits<Real>::max() : lo[d] - margin;
    scene.domain_hi[d] = period.axis[d] ? std::numeric_limits<Real>::max() : hi[d] + margin;
    if (!period.axis[d] && g_norm > 0 && g[d] < 0) scene.domain_hi[d] += hi[d] - lo[d];
    if (!period.axis[d] && g_norm > 0 && g[d] > 0) scene.domain_lo[d] -= hi[d] - lo[d];
  }
}

// The fluid probes and the force probes; a point probe must lie within the kernel support of a particle.
template <int D>
void place_fluid_probes(const CaseSpec& spec, const std::string& file, Scene<D>& scene, FluidSetup<D>& f,
                        std::vector<std::string>& problems) {
  for (std::size_t pi = 0; pi < spec.probes.size(); ++pi) {
    const ProbeSpec& p = spec.probes[pi];
    if (p.type == ProbeType::displacement || p.type == ProbeType::structure_pressure) continue;
    if (p.type == ProbeType::force) {  // the loader checked that the body is a wall or a structure
      const auto body =
          std::find_if(spec.bodies.begin(), spec.bodies.end(), [&](const BodySpec& b) { return b.name == p.body; });
      const bool all_terms = p.terms == ForceTerms::all;
      scene.force_probes.push_back({p.name, static_cast<Index>(body - spec.bodies.begin()), all_terms});
      f.wall_force = f.wall_force || body->kind == ParticleKind::wall;
      f.wall_friction = f.wall_friction || (all_terms && body->kind == ParticleKind::wall);
      continue;
    }
    const Vec<D> point = to_vec<D>(p.point);
    if (p.type == ProbeType::pressure || p.type == ProbeType::velocity) {
      Real nearest = std::numeric_limits<Real>::max();
      for (const Vec<D>& x : f.x) nearest = std::min(nearest, norm2(f.period.delta(point, x)));
      if (std::sqrt(nearest) > f.fluid_kernel().support())
        problems.push_back(file + ": probes[" + std::to_string(pi) + "].point: probe '" + p.name +
                           "' is farther than the kernel support from every fluid and wall particle");
    }
    scene.fluid_probes.push_back({p.name, p.type, point});
  }
}

// The open boundaries' buffers (sim/open_boundary.hpp): the fluid particles behind each plane, within
// its buffer, become its buffer particles. The plane's point must lie in the walls' box, the buffer must
// hold the kernel's support and some fluid, and no fluid may lie behind it. An inlet's flow_rate scales
// its profile to the flow sum V u / L its buffer carries. Returns the fastest inflow over the run.
template <int D>
Real make_open_buffers(const CaseSpec& spec, const Box<D>& walls, const std::string& file, FluidSetup<D>& f,
                       std::vector<std::string>& problems) {
  const Real support = f.fluid_kernel().support();
  f.open_zones = open_zones<D>(spec, support);
  f.open_zone.assign(f.x.size(), -1);
  Real fastest = 0;
  for (std::size_t zi = 0; zi < f.open_zones.size(); ++zi) {
    OpenZone<D>& zone = f.open_zones[zi];
    const std::string path = file + ": open_boundaries[" + std::to_string(zi) + "]";
    char buf[512];
    if (spec.open_boundaries[zi].layers > 0 && zone.thickness < support) {
      std::snprintf(buf, sizeof buf,
                    "%s.layers: the buffer, %d x dx = %g m, is thinner than the kernel's support 2h = %g m; give at "
                    "least %d layers (or leave layers out)",
                    path.c_str(), spec.open_boundaries[zi].layers, zone.thickness, support,
                    static_cast<int>(std::ceil(support / spec.dx - 1e-9)));
      problems.push_back(buf);
      continue;
    }
    bool inside = true;
    for (int d = 0; d < D; ++d) inside = inside && zone.point[d] >= walls.lo[d] && zone.point[d] <= walls.hi[d];
    if (!inside) {
      problems.push_back(path +
                         ".point: the plane's point lies outside the walls' bounding box; an open boundary "
                         "must cut the channel its walls bound");
      continue;
    }
    Index buffer = 0, behind = 0;
    Real flow = 0;
    for (std::size_t a = 0; a < f.x.size(); ++a) {
      const Real depth = zone.depth(f.x[a]);
      if (f.kind[a] != FluidKind::fluid || f.open_zone[a] >= 0 || !(depth > 0)) continue;
      if (depth > zone.thickness) {
        ++behind;
        continue;
      }
      ++buffer;
      f.open_zone[a] = static_cast<Index>(zi);
      f.kind[a] = FluidKind::wall;
      f.wall_normal[a] = zone.normal;
      f.wall_depth[a] = depth;
      f.wall_velocity[a] = f.u[a];  // an outlet's buffer moves with the fluid; an inlet's takes U (ParticleSet)
      if (!zone.outlet)
        flow += f.volume[a] * zone.speed(f.x[a], std::max(zone.ramp_time, spec.end_time)) / zone.thickness;
    }
    if (behind > 0) {
      std::snprintf(buf, sizeof buf,
                    "%s: %d fluid particles lie behind its buffer (more than %g m behind the plane); end the fluid "
                    "bodies at the buffer's far side",
                    path.c_str(), behind, zone.thickness);
      problems.push_back(buf);
    }
    if (buffer == 0) problems.push_back(path + ": no fluid particle lies in its buffer; the fluid bodies must fill it");
    if (zone.outlet || buffer == 0) continue;
    if (const Real rate = spec.open_boundaries[zi].flow_rate; rate > 0) {
      if (!(flow > 0)) {
        problems.push_back(path + ".flow_rate: the velocity's shape carries no flow to scale");
        continue;
      }
      zone.scale = rate / flow;
    }
    constexpr int samples = 200;
    for (std::size_t a = 0; a < f.x.size(); ++a)
      if (f.open_zone[a] == static_cast<Index>(zi))
        for (int k = 0; k <= samples; ++k)
          fastest = std::max(fastest, std::abs(zone.speed(f.x[a], spec.end_time * k / samples)));
  }
  return fastest;
}

}  // namespace

// Appends a fluid or wall body's lattice points to the fluid set-up.
template <int D>
void add_fluid_body(const CaseSpec& spec, std::size_t bi, const std::vector<Vec<D>>& points, int level,
                    FluidSetup<D>& f) {
  const BodySpec& body = spec.bodies[bi];
  const bool is_fluid = body.kind == ParticleKind::fluid;
  const Real volume = cell_volume<D>(body.shape, spec.dx);
  const bool moves = !is_fluid && body.motion.type != MotionType::none;
  if (moves) f.motions.emplace_back(body.motion);
  f.motion.resize(f.x.size(), -1);
  f.body.insert(f.body.end(), points.size(), static_cast<Index>(bi));
  for (const auto& p : points) {
    const Vec<D> wall_velocity = moves ? f.motions.back().velocity(p, 0) : Vec<D>::zero();
    f.id.push_back(static_cast<Index>(f.x.size()));
    f.x.push_back(p);
    f.u.push_back(is_fluid ? initial_velocity<D>(body.initial_velocity, p) : wall_velocity);
    f.volume.push_back(volume);
    f.kind.push_back(is_fluid ? FluidKind::fluid : FluidKind::wall);
    f.level.push_back(static_cast<unsigned char>(level));
    f.wall_velocity.push_back(wall_velocity);
    f.motion.push_back(moves ? static_cast<Index>(f.motions.size()) - 1 : -1);
    if (!f.structure_index.empty()) f.structure_index.push_back(-1);
  }
}

// Appends a structure particle of the given volume to the fluid set-up, where it acts as a moving
// boundary (coupled cases).
template <int D>
void add_structure_particle(const Vec<D>& x, const Vec<D>& v, Index structure_index, Real volume, int level,
                            std::size_t body, FluidSetup<D>& f) {
  f.structure_index.resize(f.x.size(), -1);
  f.id.push_back(static_cast<Index>(f.x.size()));
  f.x.push_back(x);
  f.u.push_back(v);
  f.volume.push_back(volume);
  f.kind.push_back(FluidKind::structure);
  f.level.push_back(static_cast<unsigned char>(level));
  f.wall_velocity.push_back(v);
  f.structure_index.push_back(structure_index);
  f.body.push_back(static_cast<Index>(body));
  f.motion.resize(f.x.size(), -1);
}

template <int D>
void finish_fluid(const CaseSpec& spec, Scene<D>& scene, FluidSetup<D>& f, const TlsphSetup<D>& structure,
                  std::vector<std::string>& problems) {
  const std::string file = spec.source_path.empty() ? spec.name : spec.source_path;
  const Resolutions resolutions(spec);
  configure_fluid(spec, resolutions, f);
  set_fluid_material(spec, file, f, problems);
  for (const FluidKind kind : f.kind) {
    scene.fluid_particles += kind == FluidKind::fluid;
    scene.wall_particles += kind == FluidKind::wall;
  }
  if (scene.fluid_particles == 0) {
    problems.push_back(file + ": bodies: stages.fluid is on but no fluid body has particles");
    return;
  }
  if (f.motions.size() > static_cast<std::size_t>(kMaxMotions))
    problems.push_back(file + ": bodies: " + std::to_string(f.motions.size()) + " moving wall bodies; at most " +
                       std::to_string(kMaxMotions) + " are supported");
  check_periodic_range(f, file, problems);
  check_overlaps(spec, f, file, problems);
  Box<D> box = check_containment(f, scene.wall_particles, file, problems);
  const Real support = f.fluid_kernel().support();
  const std::vector<unsigned char> unchecked =
      wall_surface_geometry(spec, f, structure.fixed, resolutions.spacing, support, f.period, f.gravity);
  check_wall_thickness(spec, f, unchecked, support, f.period, file, problems);
  const std::size_t known_problems = problems.size();
  const Real inflow = make_open_buffers(spec, box, file, f, problems);
  if (!f.open_zones.empty()) {
    scene.fluid_particles = static_cast<Index>(std::count(f.kind.begin(), f.kind.end(), FluidKind::fluid));
    scene.wall_particles = static_cast<Index>(std::count(f.kind.begin(), f.kind.end(), FluidKind::wall));
  }
  if (problems.size() == known_problems)  // a rejected inlet gives no speed: no second message
    set_reference_velocity(spec, std::max(inflow, boundary_speed(spec, f, structure, box)), file, f, problems);
  set_escape_box(f, box, scene);
  place_fluid_probes(spec, file, scene, f, problems);
}

#define ISPH_SCENE_FLUID(D)                                                                                       \
  template void add_fluid_body<D>(const CaseSpec&, std::size_t, const std::vector<Vec<D>>&, int, FluidSetup<D>&); \
  template void add_structure_particle<D>(const Vec<D>&, const Vec<D>&, Index, Real, int, std::size_t,            \
                                          FluidSetup<D>&);                                                        \
  template void finish_fluid<D>(const CaseSpec&, Scene<D>&, FluidSetup<D>&, const TlsphSetup<D>&,                 \
                                std::vector<std::string>&);
ISPH_SCENE_FLUID(2)
ISPH_SCENE_FLUID(3)
#undef ISPH_SCENE_FLUID

}  // namespace isph
