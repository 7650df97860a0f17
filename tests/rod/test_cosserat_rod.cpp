// The Cosserat rod's invariants (docs/model/26-rod.md): no force at its rest shape (a shaped tip included) or
// after a rigid motion, the balance of forces and moments, and its gradient and Hessian against central
// differences of its energy and gradient.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "vascsim/core/error.hpp"
#include "vascsim/rod/cosserat_rod.hpp"

namespace vascsim::rod {
namespace {

// A 0.035-inch wire of 60 GPa (nitinol's order), 10 mm long in 8 edges, with a J tip of 2 mm radius over 120
// degrees: natural curvature and a twist-free frame along it.
RodSection j_tip_wire() {
  return RodSection{0.889e-3, 0.0, 60e9, 60e9 / (2.0 * 1.33)};
}

CosseratRod j_tip_rod() {
  return CosseratRod(shaped_tip_rod(Vec3(0.01, -0.02, 0.003), Vec3(1, 0.2, 0), Vec3(0, 0, 1), 10e-3, 8, 2e-3,
                                    2.0 * std::numbers::pi / 3.0),
                     rod_stiffness(j_tip_wire()));
}

// The rod moved away from rest: every node by up to 5 % of an edge, every frame turned by up to 0.2 rad.
void perturb(CosseratRod& rod, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd d(rod.num_dofs());
  const double l = rod.length() / rod.num_edges();
  for (Index k = 0; k < rod.num_dofs(); ++k) d[k] = u(gen) * (k < 3 * rod.num_nodes() ? 0.05 * l : 0.2);
  rod.apply_increment(d);
}

// Whether each coordinate is a rotation (scales of the checks differ: N against N m).
double fd_step(const CosseratRod& rod, Index k) {
  return k < 3 * rod.num_nodes() ? 1e-6 * rod.length() / rod.num_edges() : 1e-6;
}

TEST(CosseratRod, TheRestShapeCarriesNoForceEvenWithAShapedTip) {
  CosseratRod rod = j_tip_rod();
  rod.clamp_start(rod.frames().front());
  const RodStiffness k = rod_stiffness(j_tip_wire());
  const double force_scale = k.bend_twist_n_m2[0] / (rod.length() * rod.length());  // EI / L^2, N
  // At rest every strain is the rest strain to round-off (1e-16 of an edge's stretch: forces of EA 1e-16,
  // about 4e-6 N here... far below): 1e-9 EI / L^2 leaves room for that and still catches any real stress,
  // whose forces are of order EI / L^2 or EA.
  const Eigen::VectorXd g = rod.gradient();
  EXPECT_LT(g.head(3 * rod.num_nodes()).cwiseAbs().maxCoeff(),
            1e-9 * force_scale + 1e-16 * k.shear_stretch_n[2]);
  EXPECT_LT(g.tail(3 * rod.num_edges()).cwiseAbs().maxCoeff(), 1e-9 * force_scale * rod.length());
  EXPECT_LT(rod.energy(), 1e-20 * force_scale * rod.length());
  // ... and the shape is the J asked for: the last edge is the chord of the arc from s = 8.75 mm to 10 mm,
  // the arc starting at s = 10 - 2 x 2 pi / 3 mm, so its axis has turned by the mean of the arc's angles
  // there.
  const double shaft = 10e-3 - 2e-3 * 2.0 * std::numbers::pi / 3.0;
  const double expected = 0.5 * ((8.75e-3 - shaft) + (10e-3 - shaft)) / 2e-3 * 180.0 / std::numbers::pi;
  const Vec3 first = rod.frames().front() * Vec3::UnitZ(), last = rod.frames().back() * Vec3::UnitZ();
  EXPECT_NEAR(std::acos(std::clamp(first.dot(last), -1.0, 1.0)) * 180.0 / std::numbers::pi, expected, 1e-9);
}

TEST(CosseratRod, ARigidMotionChangesNeitherItsEnergyNorItsStrain) {
  CosseratRod rod = j_tip_rod();
  perturb(rod, 3);
  const double e = rod.energy();
  const Eigen::VectorXd g = rod.gradient();
  const Quaternion Q(Eigen::AngleAxisd(1.1, Vec3(0.3, -0.5, 0.8).normalized()));
  const Vec3 t(0.04, -0.01, 0.2);
  Vec3Array x = rod.positions();
  std::vector<Quaternion> q = rod.frames();
  for (Vec3& p : x) p = Q * p + t;
  for (Quaternion& f : q) f = Q * f;
  rod.set_configuration(x, q);
  // Energies of order 1e-4 J summed over 17 terms: 1e-12 relative is a few hundred round-offs.
  EXPECT_NEAR(rod.energy(), e, 1e-12 * std::abs(e));
  const Eigen::VectorXd g2 = rod.gradient();
  for (Index i = 0; i < rod.num_nodes(); ++i)
    EXPECT_LT(
        (g2.segment<3>(CosseratRod::position_dof(i)) - Q * Vec3(g.segment<3>(CosseratRod::position_dof(i))))
            .norm(),
        1e-9 * g.cwiseAbs().maxCoeff())
        << "node " << i;
  for (Index j = 0; j < rod.num_edges();
       ++j)  // the torques are in each edge's own frame, which turned with it
    EXPECT_LT((g2.segment<3>(rod.rotation_dof(j)) - g.segment<3>(rod.rotation_dof(j))).norm(),
              1e-9 * g.tail(3 * rod.num_edges()).cwiseAbs().maxCoeff())
        << "edge " << j;
}

TEST(CosseratRod, ItsInternalForcesAndMomentsBalance) {
  // A free rod (no clamp): its internal forces sum to zero and so do their moments with the edges' torques
  // (what invariance under rigid translations and rotations means for the gradient).
  CosseratRod rod = j_tip_rod();
  perturb(rod, 5);
  const Eigen::VectorXd g = rod.gradient();
  Vec3 force = Vec3::Zero(), moment = Vec3::Zero();
  double scale_f = 0.0, scale_m = 0.0;
  for (Index i = 0; i < rod.num_nodes(); ++i) {
    const Vec3 f = g.segment<3>(CosseratRod::position_dof(i));
    force += f;
    moment += rod.positions()[static_cast<std::size_t>(i)].cross(f);
    scale_f = std::max(scale_f, f.norm());
    scale_m = std::max(scale_m, rod.positions()[static_cast<std::size_t>(i)].norm() * f.norm());
  }
  for (Index j = 0; j < rod.num_edges(); ++j)
    moment += rod.frames()[static_cast<std::size_t>(j)] * Vec3(g.segment<3>(rod.rotation_dof(j)));
  // Sums of 9 forces of up to scale_f: 1e-12 relative is far above round-off, far below any missing term.
  EXPECT_LT(force.norm(), 1e-12 * scale_f);
  EXPECT_LT(moment.norm(), 1e-12 * scale_m);
}

TEST(CosseratRod, ItsGradientIsTheDerivativeOfItsEnergy) {
  CosseratRod rod = j_tip_rod();
  rod.clamp_start(rod.frames().front());
  rod.clamp_end(rod.frames().back());
  perturb(rod, 7);
  const Eigen::VectorXd g = rod.gradient();
  const Vec3Array x = rod.positions();
  const std::vector<Quaternion> q = rod.frames();
  for (Index k = 0; k < rod.num_dofs(); ++k) {
    const double h = fd_step(rod, k);
    Eigen::VectorXd d = Eigen::VectorXd::Zero(rod.num_dofs());
    d[k] = h;
    rod.apply_increment(d);
    const double ep = rod.energy();
    rod.set_configuration(x, q);
    rod.apply_increment(d, -1.0);
    const double em = rod.energy();
    rod.set_configuration(x, q);
    const double fd = (ep - em) / (2.0 * h);
    // Central differences with steps of 1e-6 (of an edge, of a radian): truncation ~1e-12 relative, round-off
    // of the energy (~1e-16 E / 1e-6) ~1e-10 of E per unit step; 1e-6 of the largest gradient of the same
    // kind catches any wrong term.
    const double scale = k < 3 * rod.num_nodes() ? g.head(3 * rod.num_nodes()).cwiseAbs().maxCoeff()
                                                 : g.tail(3 * rod.num_edges()).cwiseAbs().maxCoeff();
    EXPECT_NEAR(g[k], fd, 1e-6 * scale) << "coordinate " << k;
  }
}

TEST(CosseratRod, ItsHessianIsTheDerivativeOfItsGradient) {
  CosseratRod rod = j_tip_rod();
  rod.clamp_start(rod.frames().front());
  rod.clamp_end(rod.frames().back());
  perturb(rod, 11);
  const Eigen::MatrixXd H = Eigen::MatrixXd(rod.hessian());
  const Vec3Array x = rod.positions();
  const std::vector<Quaternion> q = rod.frames();
  Eigen::MatrixXd J(rod.num_dofs(), rod.num_dofs());
  for (Index k = 0; k < rod.num_dofs(); ++k) {
    const double h = fd_step(rod, k);
    Eigen::VectorXd d = Eigen::VectorXd::Zero(rod.num_dofs());
    d[k] = h;
    rod.apply_increment(d);
    const Eigen::VectorXd gp = rod.gradient();
    rod.set_configuration(x, q);
    rod.apply_increment(d, -1.0);
    const Eigen::VectorXd gm = rod.gradient();
    rod.set_configuration(x, q);
    J.col(k) = (gp - gm) / (2.0 * h);
  }
  // The gradient's rotational part is taken in each edge's own (moving) frame, so differencing it adds the
  // antisymmetric 1/2 [g]x on each edge's rotation block; the Hessian is the symmetric part.
  const Eigen::MatrixXd S = 0.5 * (J + J.transpose());
  EXPECT_LT((H - H.transpose()).cwiseAbs().maxCoeff(), 1e-12 * H.cwiseAbs().maxCoeff());
  for (Index r = 0; r < rod.num_dofs(); ++r)
    for (Index c = 0; c < rod.num_dofs(); ++c) {
      // Each entry against its own scale sqrt(|H_rr H_cc|): the stretch entries (EA / l) are 10^7 times the
      // bending ones (EI / l), and a bending term must not hide in the stretch's round-off. 1e-5 is well
      // above the differences' error (~1e-8 here) and well below any wrong term.
      const double scale = std::sqrt(std::abs(H(r, r) * H(c, c)));
      EXPECT_NEAR(H(r, c), S(r, c), 1e-5 * scale) << "entry (" << r << ", " << c << ")";
    }
}

TEST(CosseratRod, BadInputIsAnInputError) {
  EXPECT_THROW(rod_stiffness(RodSection{0.0, 0.0, 60e9, 20e9}), InputError);
  EXPECT_THROW(rod_stiffness(RodSection{1e-3, 1e-3, 60e9, 20e9}), InputError);  // no wall left
  EXPECT_THROW(rod_stiffness(RodSection{1e-3, 0.0, 60e9, 10e9}), InputError);   // nu = 2
  EXPECT_THROW(straight_rod(Vec3::Zero(), Vec3::UnitX(), Vec3::UnitX(), 0.01, 4), InputError);
  EXPECT_THROW(straight_rod(Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), 0.01, 0), InputError);
  EXPECT_THROW(shaped_tip_rod(Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), 0.01, 10, 0.01, std::numbers::pi),
               InputError);
}

}  // namespace
}  // namespace vascsim::rod
