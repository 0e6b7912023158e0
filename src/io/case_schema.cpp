#include "io/case_schema.hpp"

#include <algorithm>
#include <stdexcept>

#include "io/list_schema.hpp"
#include "io/schema_declaration.hpp"
#include "poisson/linear_solver.hpp"

namespace isph {

namespace {

using namespace schema_declaration;

std::vector<SettingKey> declare_keys() {
  std::vector<SettingKey> keys;
  // top level
  add(
      keys, "", "name", [](auto& c) -> auto& { return c.name; })
      .default_text("file stem")
      .doc("case name; not empty");
  add(
      keys, "", "dimension", [](auto& c) -> auto& { return c.dimension; })
      .bounds(KeyBounds{2, 3})
      .doc("sets the length of every vector and the shape types");
  add(
      keys, "", "dx", [](auto& c) -> auto& { return c.dx; })
      .unit("m")
      .bounds(positive())
      .required()
      .doc("particle spacing of the fluid and the walls (and of structures unless they set their own)");
  add(
      keys, "", "end_time", [](auto& c) -> auto& { return c.end_time; })
      .unit("s")
      .bounds(positive())
      .required()
      .doc("simulated time");
  add(
      keys, "", "gravity", [](auto& c) -> auto& { return c.gravity; })
      .unit("m/s²")
      .default_text("zeros")
      .doc("gravitational acceleration");
  // [kernel]
  add(
      keys, "kernel", "type", [](auto& c) -> auto& { return c.kernel.type; })
      .doc("the smoothing kernel (kernels/smoothing_kernel.hpp)");
  add(
      keys, "kernel", "h_factor", [](auto& c) -> auto& { return c.kernel.h_factor; })
      .bounds(positive())
      .doc("smoothing length h = h_factor · dx");
  add(
      keys, "kernel", "correction", [](auto& c) -> auto& { return c.kernel.correction; })
      .doc("kernel gradient correction");
  // [structure]
  add(
      keys, "structure", "integrator", [](auto& c) -> auto& { return c.structure.integrator; })
      .doc("RK4 (the seed) or velocity-Verlet, for the structure substeps");
  add(
      keys, "structure", "gradient", [](auto& c) -> auto& { return c.structure.gradient; })
      .doc(
          R"d(`"linear"`: pair gradients L_a g_ab, exact for linear fields (seed Eq. 35-36); `"quadratic"`: exact for quadratic fields also at free surfaces and corners, with a symmetric hourglass error that does not stiffen smooth bending. Quadratic makes the bending stiffness nearly independent of `hourglass` (docs/VALIDATION.md section 21). Ignored when `kernel.correction = false`)d");
  add(
      keys, "structure", "quadrature", [](auto& c) -> auto& { return c.structure.quadrature; })
      .doc(
          R"d(the strain energy of a particle: `"point"`: evaluated at the particle (SPH's one-point rule; across N particle rows it underestimates the bending stiffness by 1/N²); `"cell"`: integrated over the particle's cell with the strain's linear variation across it, exact for St. Venant-Kirchhoff when the strain is linear in the cell; two more neighbour passes per evaluation (docs/VALIDATION.md section 22))d");
  add(
      keys, "structure", "courant", [](auto& c) -> auto& { return c.structure.courant; })
      .bounds(positive())
      .doc("dt = courant · h / c_p (c_p: P-wave speed)");
  add(
      keys, "structure", "damping", [](auto& c) -> auto& { return c.structure.damping; })
      .unit("1/s")
      .bounds(non_negative())
      .doc("mass-proportional damping rate");
  add(
      keys, "structure", "hourglass", [](auto& c) -> auto& { return c.structure.hourglass; })
      .bounds(non_negative())
      .doc("Ganzenmüller (2015) hourglass control coefficient α (0 = off); see docs/VALIDATION.md for its effect");
  // [fluid]
  add(
      keys, "fluid", "model", [](auto& c) -> auto& { return c.fluid.model; })
      .doc(R"d(`"isph"`; `"wcsph"`: the weakly compressible comparator (sim/wcsph.hpp))d");
  add(
      keys, "fluid", "courant", [](auto& c) -> auto& { return c.fluid.courant; })
      .bounds(positive())
      .doc("dt = courant · h / U (Eq. 49)");
  add(
      keys, "fluid", "viscous_number", [](auto& c) -> auto& { return c.fluid.viscous_number; })
      .bounds(positive())
      .doc("dt <= viscous_number · h² / ν");
  add(
      keys, "fluid", "reference_velocity", [](auto& c) -> auto& { return c.fluid.reference_velocity; })
      .unit("m/s")
      .bounds(non_negative())
      .doc(
          "floor on U in Eq. 49. 0: √(2 |g| H), H the fluid's vertical extent, or the fastest moving wall or clamp if "
          "faster");
  add(
      keys, "fluid", "max_dt", [](auto& c) -> auto& { return c.fluid.max_dt; })
      .unit("s")
      .bounds(non_negative())
      .doc("cap on dt (0: no cap)");
  add(
      keys, "fluid", "turbulence", [](auto& c) -> auto& { return c.fluid.turbulence; })
      .doc(R"d(`"none"`, `"sps"` (sub-particle-scale Smagorinsky model, Eq. 10))d");
  add(
      keys, "fluid", "smagorinsky", [](auto& c) -> auto& { return c.fluid.smagorinsky; })
      .bounds(positive())
      .doc("c_s of Eq. 10");
  add(
      keys, "fluid", "free_surface", [](auto& c) -> auto& { return c.fluid.free_surface; })
      .doc(
          "detect the free surface (Dirichlet p = 0 there, Eq. 17); `false`: a confined flow, whose projection keeps "
          "no kinematic wall condition (docs/VALIDATION.md §35)");
  add(
      keys, "fluid", "surface_threshold", [](auto& c) -> auto& { return c.fluid.surface_threshold; })
      .bounds(non_negative())
      .doc("particles with ∇·r below it are surface particles. 0: 1.4 in 2D, 2.4 in 3D");
  add(
      keys, "fluid", "surface_full", [](auto& c) -> auto& { return c.fluid.surface_full; })
      .bounds(non_negative())
      .doc(
          "∇·r above it: Skillen α = 1. 0: 1.6 in 2D, 2.6 in 3D. Must be > `surface_threshold` (judged with the "
          "defaults in place of zeros)");
  add(
      keys, "fluid", "surface_pressure", [](auto& c) -> auto& { return c.fluid.surface_pressure; })
      .doc(
          R"d(condition at free-surface particles: `"zero"`: p = 0 (the seed's Dirichlet condition); `"extrapolated"`: p = 0 half a spacing beyond the particle, along its outward normal (p_a + (dx/2) n·∇p_a = 0), which removes the ρg·dx/2 offset that `"zero"` gives still water)d");
  add(
      keys, "fluid", "escape", [](auto& c) -> auto& { return c.fluid.escape; })
      .doc(
          R"d(a fluid particle that leaves the escape box (the box of all particles grown by 2h, and upwards, against gravity, by its own height; moving walls' paths widen it): `"remove"`: when it left above the set-up's highest particle less one kernel support 2h (thrown out over the walls, or over their top corner; so a particle that leaks through the top 2h of a wall is removed too) it is taken out of the run, which goes on (the progress output says so; summary.json gives `particles.fluid_removed` and `particles.fluid_first_removed_at`; its energy leaves energy.csv with it); `"stop"`: the run stops as diverged, naming the particle. A particle that left below that height (through a wall or the floor: a numerical failure) stops the run either way)d");
  add(
      keys, "fluid", "density_relaxation", [](auto& c) -> auto& { return c.fluid.density_relaxation; })
      .bounds({0, 1})
      .doc(
          "γ: the PPE's source in full rows gains γ (1 − σ / σ₀) / Δt², σ = Σ V W the particles' kernel sum and σ₀ "
          "its value on a regular lattice, so that a region whose particles have spread is drawn together by the "
          "fraction γ of its deficit per step "
          "(a density-invariant term after Asai et al. 2012); 0: the seed's divergence-free source alone. Open "
          "channels with obstacles need it (docs/VALIDATION.md section 35)");
  add(
      keys, "fluid", "constraint_weight", [](auto& c) -> auto& { return c.fluid.constraint_weight; })
      .bounds({0.5, 1})
      .doc(
          "θ: the projection makes θ u^{n+1} + (1 − θ) u^n divergence-free at the step's positions, the PPE's "
          "source becoming ∇·(u* + ((1 − θ)/θ) u^n); 1: u^{n+1} alone (the seed's Eq. 14). That takes "
          "½ Δt² |∇p/ρ|² of kinetic energy per step from a particle the pressure turns (a numerical drag, first "
          "order in Δt); θ takes 2θ − 1 times it, and damps a step-to-step swing of the pressure by (1 − θ)/θ "
          "per step (none at 0.5). Confined flows around obstacles: 0.6 halves the channel's time-step error "
          "(docs/VALIDATION.md section 36)");
  // [fluid.shifting]
  add(
      keys, "fluid.shifting", "type", [](auto& c) -> auto& { return c.fluid.shifting.type; })
      .doc(
          R"d(`"none"`; `"xu"`: Xu et al. (2009) / Lind et al. (2012) shifting (seed 001 Eqs. 21-23), |δr| capped at max_fraction · h; `"ops"`: `"xu"` plus the optimized particle shifting of Khayyer et al. (2017) at the free surface (tangential only, Eqs. 24-26))d");
  add(
      keys, "fluid.shifting", "coefficient", [](auto& c) -> auto& { return c.fluid.shifting.coefficient; })
      .bounds(KeyBounds{0, 1, true, false})
      .doc("C of Eq. 21 (0.01-0.1 is the usual range)");
  add(
      keys, "fluid.shifting", "max_fraction", [](auto& c) -> auto& { return c.fluid.shifting.max_fraction; })
      .bounds(positive())
      .doc("cap on |δr| as a fraction of h (Lind et al. 2012)");
  add(
      keys, "fluid.shifting", "taylor_correction", [](auto& c) -> auto& { return c.fluid.shifting.taylor_correction; })
      .doc("correct the shifted particles' velocity and pressure by a Taylor expansion (Eqs. 20, 31-32)");
  // [fluid.collision]
  add(
      keys, "fluid.collision", "distance", [](auto& c) -> auto& { return c.fluid.collision.distance; })
      .bounds(KeyBounds{0, 1})
      .doc(
          "fluid particles closer than distance · dx that still approach each other collide inelastically "
          "(ISPH; docs/CASES.md). 0: no collisions");
  add(
      keys, "fluid.collision", "restitution", [](auto& c) -> auto& { return c.fluid.collision.restitution; })
      .bounds(KeyBounds{0, 1})
      .doc("e: the share of the approaching velocity a collision reverses (0: fully inelastic)");
  // [fluid.ppe]
  add(
      keys, "fluid.ppe", "backend", [](auto& c) -> auto& { return c.fluid.ppe.backend; })
      .default_text(R"d(`"hypre"` in builds with hypre, `"eigen"` otherwise)d")
      .doc(
          R"d(`"eigen"`, `"hypre"` (only in builds with hypre; the run reports it otherwise), `"native"` (the project's BiCGSTAB on the host), `"cuda"` (the same BiCGSTAB on the GPU with cuSPARSE; needs a build with CUDA and a visible device, the run reports it otherwise))d");
  add(
      keys, "fluid.ppe", "method", [](auto& c) -> auto& { return c.fluid.ppe.method; })
      .doc("gmres: eigen and hypre only");
  add(
      keys, "fluid.ppe", "preconditioner", [](auto& c) -> auto& { return c.fluid.ppe.preconditioner; })
      .default_text(R"d(`"ilu"` for eigen, `"boomeramg"` for hypre, `"jacobi"` for native and cuda)d")
      .doc(
          R"d(eigen: `"jacobi"`, `"ilu"`, `"none"`; hypre: `"boomeramg"`, `"jacobi"`, `"none"`; native, cuda: `"jacobi"`, `"polynomial"` (three damped Jacobi sweeps), `"amg"` (smoothed-aggregation AMG, one V-cycle; docs/SOLVERS.md), `"none"`; another combination is an error)d");
  add(
      keys, "fluid.ppe", "tolerance", [](auto& c) -> auto& { return c.fluid.ppe.tolerance; })
      .bounds(open_unit())
      .doc("relative residual ||b − Ax|| / ||b||");
  add(
      keys, "fluid.ppe", "max_iterations", [](auto& c) -> auto& { return c.fluid.ppe.max_iterations; })
      .bounds(KeyBounds{1})
      .doc("Krylov iterations per solve");
  add(
      keys, "fluid.ppe", "fallback", [](auto& c) -> auto& { return c.fluid.ppe.fallback; })
      .default_text(
          R"d(`"eigen"` when `backend` is not given and the build has hypre, `"none"` otherwise (a case that names a backend names its fallback too))d")
      .doc(
          R"d(`"none"`, `"eigen"`, `"hypre"`: a second backend tried after a failed solve; must differ from `backend`)d");
  add(
      keys, "fluid.ppe", "preconditioner_reuse", [](auto& c) -> auto& { return c.fluid.ppe.preconditioner_reuse; })
      .bounds(KeyBounds{0, 1000})
      .doc(
          "keep the AMG hierarchy for up to this many further fluid steps, the Krylov method taking each new "
          "matrix; when it is dropped and what it saves: below the table");
  // [fluid.wcsph]
  add(
      keys, "fluid.wcsph", "time_stepping", [](auto& c) -> auto& { return c.fluid.wcsph.time_stepping; })
      .doc(
          R"d(`"dual_criteria"`: advection steps (Eq. 9) that rebuild the neighbour list, reinitialise the density (Eqs. 11-12) and compute the viscous force, each split into acoustic velocity-Verlet steps (Eqs. 10, 13-15) that reuse the list; `"single_criterion"`: every step an acoustic step that rebuilds the list, no reinitialisation)d");
  add(
      keys, "fluid.wcsph", "advection_courant", [](auto& c) -> auto& { return c.fluid.wcsph.advection_courant; })
      .bounds(positive())
      .doc(
          "CFL_ad of Eq. 9: dt_ad = CFL_ad min(h/U, h²/ν), U the fastest fluid particle, at least "
          "`fluid.reference_velocity` (resolved as for ISPH)");
  add(
      keys, "fluid.wcsph", "acoustic_courant", [](auto& c) -> auto& { return c.fluid.wcsph.acoustic_courant; })
      .bounds(positive())
      .default_text("`0.6` (dual_criteria), `0.25` (single_criterion)")
      .doc("CFL_ac of Eq. 10: dt_ac <= CFL_ac h/(c + U)");
  add(
      keys, "fluid.wcsph", "sound_speed", [](auto& c) -> auto& { return c.fluid.wcsph.sound_speed; })
      .unit("m/s")
      .bounds(non_negative())
      .doc("c of Eq. 2. 0: 10 U_max with U_max = 2√(gH) (seed 002 §3.1), i.e. 10√2 times the reference velocity");
  add(
      keys, "fluid.wcsph", "riemann_limiter", [](auto& c) -> auto& { return c.fluid.wcsph.riemann_limiter; })
      .bounds(non_negative())
      .doc(
          "η of the low-dissipation limiter β = min(η max(U_L − U_R, 0)/c, 1) on the Riemann pressure's dissipation; "
          "0: β = 1 (the plain acoustic Riemann solver; on the dam break at a/20 it slows the surge front badly, RMSE "
          "0.98 against 0.43)");
  // [coupling]
  add(
      keys, "coupling", "substeps", [](auto& c) -> auto& { return c.coupling.substeps; })
      .bounds(KeyBounds{0, 1000000})
      .doc(
          "structure (TLSPH) steps per fluid step; `0`: ceil(dt_fluid / dt_structure) each fluid step, with "
          "dt_structure from `structure.courant`; a count fixes the ratio (the seed uses 100), for comparison");
  add(
      keys, "coupling", "fsi_shifting", [](auto& c) -> auto& { return c.coupling.fsi_shifting; })
      .doc(
          "the FSI shifting layer (seed Eqs. 27-30) for fluid particles beside a structure, which changes their shift "
          "along the structure's normal by `fsi_shifting_law`; what it does to the shipped cases: below the table");
  add(
      keys, "coupling", "fsi_shifting_law", [](auto& c) -> auto& { return c.coupling.fsi_shifting_law; })
      .doc(
          R"d(what the layer's Eq. 27, x → x + |d| (exp(−x/|d|) − 1) with |d| from Eq. 29, relocates: `"literal"`: Xu's normal shift (the seed's text), which keeps about C²R_n² of it; `"derived"`: the convection distance |u|_max Δt (the seed's Eq. 28), which gives back Xu's normal shift to second order and caps it at |u|_max Δt; `"relative"` (not the seed's): each particle's own convection distance past the nearest structure particle, |u_a − u_s| Δt, which keeps Xu's normal shift where the water flows past the structure and stops it where the water moves with it (docs/VALIDATION.md §26))d");
  add(
      keys, "coupling", "interaction_force", [](auto& c) -> auto& { return c.coupling.interaction_force; })
      .doc(
          R"d(the pressure force on structure particles: `"pairwise"`: symmetric SPH pressure force from the fluid neighbours (equal and opposite pair by pair); `"gradient"`: Eq. 48 literally, the corrected pressure gradient over all neighbours (docs/VALIDATION.md compares them))d");
  add(
      keys, "coupling", "substep_interaction", [](auto& c) -> auto& { return c.coupling.substep_interaction; })
      .doc(
          R"d(the interaction acceleration α(f→s) over the substeps: `"held"`: the value from the pressure of the step's end, in every substep; `"interpolated"`: linear in time from the last step's converged value to it (docs/VALIDATION.md §12 measures the difference; two thirds of the load in a step's chord displacement are then the previous step's, and a structure mode whose added mass exceeds three times its own mass flips sign every fluid step and grows: it diverges on the bundled hydrostatic plate))d");
  add(
      keys, "coupling", "tolerance", [](auto& c) -> auto& { return c.coupling.tolerance; })
      .bounds(open_unit())
      .doc("interface iterations stop when the change of the structure's acceleration is below tol times its size");
  add(
      keys, "coupling", "max_iterations", [](auto& c) -> auto& { return c.coupling.max_iterations; })
      .bounds(KeyBounds{1})
      .doc(
          "interface iterations per fluid step; `1` is the staggered (explicit) scheme, unstable when the fluid's "
          "added mass exceeds the structure's and `implicit_added_mass` is off; the shipped cases' `2` and the "
          "residual summary.json reports: below the table");
  add(
      keys, "coupling", "first_ppe_tolerance", [](auto& c) -> auto& { return c.coupling.first_ppe_tolerance; })
      .bounds(KeyBounds{0, 1, false, true})
      .doc(
          "`0`: the PPE's own `fluid.ppe.tolerance`; otherwise the PPE tolerance of each fluid step's first interface "
          "iteration, when `max_iterations` > 1 (below the table)");
  add(
      keys, "coupling", "implicit_added_mass", [](auto& c) -> auto& { return c.coupling.implicit_added_mass; })
      .doc(
          "the structure's inertia in its PPE rows (below the table); `false`: the rows take the structure's "
          "acceleration as given (the seed's scheme)");
  add(
      keys, "coupling", "reuse_steps", [](auto& c) -> auto& { return c.coupling.reuse_steps; })
      .bounds(KeyBounds{0, 100})
      .doc("earlier fluid steps whose iterations the quasi-Newton method (IQN-ILS) reuses");
  add(
      keys, "coupling", "wall_contact", [](auto& c) -> auto& { return c.coupling.wall_contact; })
      .doc("structure-wall contact: a penalty that pushes a structure particle out of the walls (below the table)");
  // [output]
  add(
      keys, "output", "interval", [](auto& c) -> auto& { return c.output.interval; })
      .unit("s")
      .bounds(non_negative())
      .doc("probes and energies every interval (0: every 100 steps)");
  add(
      keys, "output", "snapshot_interval", [](auto& c) -> auto& { return c.output.snapshot_interval; })
      .unit("s")
      .bounds(non_negative())
      .doc("snapshot every interval (0: first and last only)");
  add(
      keys, "output", "snapshots", [](auto& c) -> auto& { return c.output.snapshots; })
      .doc("write HDF5 snapshots");
  // [stages]
  add(
      keys, "stages", "structure", [](auto& c) -> auto& { return c.stages.structure; })
      .doc(R"d(run the structure solver (TLSPH); needs at least one `"structure"` body)d");
  add(
      keys, "stages", "fluid", [](auto& c) -> auto& { return c.stages.fluid; })
      .doc(R"d(run the fluid solver (ISPH); needs at least one `"fluid"` body)d");
  return keys;
}

}  // namespace

const std::vector<SettingKey>& case_keys() {
  static const std::vector<SettingKey> keys = declare_keys();
  return keys;
}

const std::vector<std::string>& case_sections() {
  static const std::vector<std::string> sections = [] {
    std::vector<std::string> s;
    for (const SettingKey& k : case_keys())
      if (std::find(s.begin(), s.end(), k.section) == s.end()) s.push_back(k.section);
    return s;
  }();
  return sections;
}

std::string key_reference(const std::string& section) {
  const CaseSpec defaults;
  std::string table = reference_head(false);
  for (const SettingKey& k : case_keys())
    if (k.section == section) table += reference_row(k, defaults, false);
  return table;
}

std::string with_key_reference(const std::string& document) {
  static const std::string open = "<!-- keys ", close = "<!-- end keys -->";
  std::string out;
  std::vector<std::string> seen;
  std::size_t at = 0;
  for (std::size_t start; (start = document.find(open, at)) != std::string::npos;) {
    const std::size_t name_end = document.find(" -->", start);
    const std::size_t end = document.find(close, start);
    if (name_end == std::string::npos || end == std::string::npos)
      throw std::runtime_error("an unclosed \"" + open + "\" block");
    const std::string marked = document.substr(start + open.size(), name_end - start - open.size());
    const std::string section = marked == "top" ? "" : marked;
    const bool list = std::find(list_tables().begin(), list_tables().end(), section) != list_tables().end();
    if (!list && std::find(case_sections().begin(), case_sections().end(), section) == case_sections().end())
      throw std::runtime_error("a key block of an unknown section \"" + marked + "\"");
    seen.push_back(section);
    out += document.substr(at, name_end + 4 - at) + "\n" +
           (list ? list_key_reference(section) : key_reference(section)) + close;
    at = end + close.size();
  }
  out += document.substr(at);
  std::vector<std::string> every = case_sections();
  every.insert(every.end(), list_tables().begin(), list_tables().end());
  for (const std::string& section : every)
    if (std::find(seen.begin(), seen.end(), section) == seen.end())
      throw std::runtime_error("no key block for section \"" + (section.empty() ? "top" : section) + "\"");
  return out;
}

}  // namespace isph
