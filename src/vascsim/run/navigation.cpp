#include "vascsim/run/navigation.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "vascsim/core/atomic_file.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/core/stopwatch.hpp"
#include "vascsim/rod/centerline_lumen.hpp"
#include "vascsim/rod/instrument.hpp"
#include "vascsim/rod/lumen_contact.hpp"
#include "vascsim/rod/lumen_friction.hpp"
#include "vascsim/rod/rod_feeder.hpp"
#include "vascsim/rod/rod_statics.hpp"

namespace vascsim {

namespace {

using rod::CosseratRod;

// The hand's force along the port's axis and moment about it, from the rod's elastic forces on the
// coordinates the port holds (at an equilibrium, what holds them balances them).
std::pair<double, double> hand_load(const CosseratRod& r, const std::vector<char>& held, const Vec3& axis) {
  const Eigen::VectorXd g = r.gradient();
  double force = 0.0, torque = 0.0;
  for (Index i = 0; i < r.num_nodes(); ++i)
    if (held[static_cast<std::size_t>(CosseratRod::position_dof(i))])
      force += g.segment<3>(CosseratRod::position_dof(i)).dot(axis);
  // The held edges lie on the port's axis: the moment about the axis is the rotation's third component.
  for (Index j = 0; j < r.num_edges(); ++j)
    if (held[static_cast<std::size_t>(r.rotation_dof(j) + 2)]) torque += g[r.rotation_dof(j) + 2];
  return {force, torque};
}

void write_frames(const std::filesystem::path& file, const std::vector<NavigationFrame>& frames) {
  std::ostringstream o;
  o << "time_s,inserted_m,twist_rad,tip_x_m,tip_y_m,tip_z_m,tip_s_m,insertion_force_n,torque_n_m,"
       "wall_force_max_n,wall_force_total_n,nodes_in_contact,outside_max_m,newton_iterations,converged,"
       "perforation_risk,wall_ms\n";
  for (const NavigationFrame& f : frames)
    o << fmt::format(
        "{:.6g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.6g},{:.6g},{:.6g},{:.6g},{},{:.4g},{},{},{},{:."
        "3f}\n",
        f.time_s, f.inserted_m, f.twist_rad, f.tip_m.x(), f.tip_m.y(), f.tip_m.z(), f.tip_s_m,
        f.insertion_force_n, f.torque_n_m, f.wall_force_max_n, f.wall_force_total_n, f.nodes_in_contact,
        f.outside_max_m, f.newton_iterations, f.converged ? 1 : 0, f.perforation_risk ? 1 : 0, f.wall_ms);
  write_file_atomically(file, o.str());
}

void write_shape(const std::filesystem::path& file, const Vec3Array& x) {
  std::ostringstream o;
  o << "node,x_m,y_m,z_m\n";
  for (std::size_t i = 0; i < x.size(); ++i)
    o << fmt::format("{},{:.9g},{:.9g},{:.9g}\n", i, x[i].x(), x[i].y(), x[i].z());
  write_file_atomically(file, o.str());
}

}  // namespace

NavigationResult run_navigation(const Scene& scene, const NavigationOptions& options) {
  if (!scene.instrument)
    throw InputError(fmt::format("{}: the scene has no 'instrument' block to navigate (docs/scene-format.md)",
                                 scene.file));
  if (scene.geometry.type != "vessel")
    throw InputError(
        fmt::format("{}: key 'instrument': navigation needs a vessel geometry with a centre-line "
                    "(geometry.type 'vessel'), not '{}'",
                    scene.file, scene.geometry.type));
  const rod::InstrumentSpec& spec = *scene.instrument;
  const double lumen_radius = scene.geometry.tube.outer_radius_m - scene.geometry.tube.wall_thickness_m;
  const double r = 0.5 * spec.section.outer_diameter_m;
  if (!(r < 0.9 * lumen_radius))
    throw InputError(
        fmt::format("{}: key 'instrument.outer_diameter_m': the instrument ({} m across) does not fit "
                    "the lumen ({} m across: the outer diameter less twice the wall)",
                    scene.file, 2.0 * r, 2.0 * lumen_radius));
  const rod::CenterlineLumen lumen(build_centerline(scene.geometry.centerline), lumen_radius);
  const Centerline& c = lumen.centerline();
  if (spec.port_s_m > c.length())
    throw InputError(fmt::format("{}: key 'instrument.port_s_m': {} m is beyond the centre-line's {} m",
                                 scene.file, spec.port_s_m, c.length()));
  const rod::AccessPort port{c.position(spec.port_s_m), c.tangent(spec.port_s_m)};
  CosseratRod rod = rod::make_instrument_rod(spec, Vec3::Zero(), port.axis, c.frame(spec.port_s_m).N);
  const auto [inserted0, twist0] = rod::drive_at(spec.drive, 0.0);
  rod::RodFeeder feeder(rod, port, inserted0);
  if (twist0 != 0.0) feeder.drive(inserted0, twist0);
  // The contact's penalty as stiff as an edge along its axis (docs/model/26-rod.md section 26.4); friction
  // sticks below a slip of a thousandth of the rod's radius per frame.
  rod::LumenContact contact(lumen, r, rod.stiffness().shear_stretch_n[2] / spec.edge_length_m);
  rod::LumenFriction friction(spec.friction, 1e-3 * r);
  const double tolerance = 0.01 * r;

  NavigationResult result;
  result.lumen_radius_m = lumen_radius;
  const double t_end = spec.drive.back().time_s;
  const int frames = static_cast<int>(std::ceil(t_end / spec.frame_s - 1e-9));
  for (int n = 0; n <= frames; ++n) {
    const double t = std::min(n * spec.frame_s, t_end);
    const Stopwatch watch;
    if (n > 0) {
      friction.begin_step(rod, contact, lumen);  // before the feed: the feed's slide is a slip
      const auto [inserted, twist] = rod::drive_at(spec.drive, t);
      feeder.drive(inserted, twist);
    }
    contact.set_exempt(feeder.outside());
    const std::vector<const rod::RodPotential*> others =
        spec.friction > 0.0 && n > 0 ? std::vector<const rod::RodPotential*>{&friction}
                                     : std::vector<const rod::RodPotential*>{};
    const rod::LumenSolveReport rep =
        rod::solve_in_lumen(rod, feeder.held(), {}, contact, tolerance, 10, {1, 100, 1e-6}, others);
    NavigationFrame f;
    f.wall_ms = watch.seconds() * 1e3;
    f.time_s = t;
    f.inserted_m = feeder.inserted_m();
    f.twist_rad = feeder.twist_rad();
    f.tip_m = rod.positions().back();
    f.tip_s_m = c.closest_arc_length(f.tip_m);
    std::tie(f.insertion_force_n, f.torque_n_m) = hand_load(rod, feeder.held(), port.axis);
    const Vec3Array forces = contact.forces(rod);
    for (const Vec3& p : forces) {
      const double m = p.norm();
      f.wall_force_max_n = std::max(f.wall_force_max_n, m);
      f.wall_force_total_n += m;
      f.wall_force_sum_n += p;
      f.nodes_in_contact += m > 0.0 ? 1 : 0;
    }
    f.outside_max_m = rod::worst_outside(rod, feeder.outside(), lumen, r);
    f.newton_iterations = rep.statics.newton_iterations;
    f.converged = rep.statics.converged && rep.max_penetration_m <= tolerance;
    f.perforation_risk = spec.perforation_force_n > 0.0 && f.wall_force_max_n > spec.perforation_force_n;
    result.unconverged += f.converged ? 0 : 1;
    result.perforation_frames += f.perforation_risk ? 1 : 0;
    result.frames.push_back(f);
    if (options.on_progress) options.on_progress(n, frames);
  }
  result.final_positions_m = rod.positions();
  if (!options.out_dir.empty()) {
    std::filesystem::create_directories(options.out_dir);
    write_frames(options.out_dir / "instrument.csv", result.frames);
    write_shape(options.out_dir / "instrument_final.csv", result.final_positions_m);
  }
  return result;
}

}  // namespace vascsim
