// Hyperelastic strain-energy laws of src/vascsim/model/materials (issue "Vessel-wall materials"):
// stress-free rest state, P = d psi/dF and dP = d P/dF[dF] against central differences, the small-strain
// limit against linear elasticity, objectivity, the stable neo-Hookean under inversion, the HGO fibre
// switch and closed forms, parameter validation, the factory, and agreement of the SVK law with
// PointPrimitiveEnergy.

#include <gtest/gtest.h>

#include "support/test_support.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "vascsim/core/error.hpp"
#include "vascsim/model/discretization.hpp"
#include "vascsim/model/materials/hgo_law.hpp"
#include "vascsim/model/materials/law_factory.hpp"
#include "vascsim/model/materials/material_frame.hpp"
#include "vascsim/model/materials/mooney_rivlin_law.hpp"
#include "vascsim/model/materials/neo_hookean_law.hpp"
#include "vascsim/model/materials/svk_law.hpp"
#include "vascsim/model/point_primitive_energy.hpp"

namespace {

using namespace vascsim;
using namespace vascsim::materials;
using test::record;

constexpr double kE = 0.5e6;  // Pa, hand dorsal vein default (docs/model/00-design-decisions.md)
constexpr double kNu = 0.45;

// Isotropic linear elasticity of (E, nu), docs/model/01-notation.md.
double lame_lambda(double E, double nu) {
  return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
}
double shear_modulus(double E, double nu) {
  return E / (2.0 * (1.0 + nu));
}

// Bulk modulus for the HGO ground matrix: kappa = 2 c (1 + nu) / (3 (1 - 2 nu)) with nu = 0.45 (9.67 c).
constexpr double kHgoBulk = 2.0 * 3.0e3 * 1.45 / (3.0 * 0.1);

// A frame not aligned with the coordinate axes, so that fibre directions have all three components.
MaterialFrame tilted_frame() {
  return make_material_frame(Vec3(0.3, -0.2, 1.0), Vec3(1.0, 0.4, 0.1));
}

struct LawCase {
  std::string label;
  std::shared_ptr<const HyperelasticLaw> law;
  MaterialFrame frame;
  double lambda, mu;  // small-strain Lame constants the law must reproduce, Pa
};

std::vector<LawCase> all_laws() {
  const double lam = lame_lambda(kE, kNu), mu = shear_modulus(kE, kNu);
  const double kappa = lam + 2.0 * mu / 3.0;
  std::vector<LawCase> c;
  c.push_back({"svk", std::make_shared<SvkLaw>(SvkParameters{kE, kNu}), tilted_frame(), lam, mu});
  c.push_back({"neo_hookean", std::make_shared<NeoHookeanLaw>(NeoHookeanParameters{kE, kNu}), tilted_frame(),
               lam, mu});
  // C10 : C01 = 7 : 3 with mu = 2 (C10 + C01).
  c.push_back({"mooney_rivlin",
               std::make_shared<MooneyRivlinLaw>(MooneyRivlinParameters{0.35 * mu, 0.15 * mu, kappa}),
               tilted_frame(), lam, mu});
  const HgoParameters media = hgo2000_carotid_media(kHgoBulk);
  c.push_back({"hgo", std::make_shared<HgoLaw>(media), tilted_frame(),
               kHgoBulk - 2.0 * media.shear_modulus_pa / 3.0, media.shear_modulus_pa});
  return c;
}

double rel_err(const Mat3& a, const Mat3& b) {
  return (a - b).norm() / b.norm();
}

Mat3 random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized().toRotationMatrix();
}

// "Near I": F = I + 0.05 B, B uniform in [-1, 1]^9. "Far": F = U diag(s) V^T with random rotations U, V
// and stretches s in [0.6, 1.7]. Both redrawn until det F > 0.3.
Mat3 random_F(std::mt19937_64& rng, bool near) {
  std::uniform_real_distribution<double> uni(-1.0, 1.0), stretch(0.6, 1.7);
  for (;;) {
    Mat3 F;
    if (near) {
      Mat3 B;
      for (int k = 0; k < 9; ++k) B(k) = uni(rng);
      F = Mat3::Identity() + 0.05 * B;
    } else {
      F = random_rotation(rng) * Vec3(stretch(rng), stretch(rng), stretch(rng)).asDiagonal() *
          random_rotation(rng).transpose();
    }
    if (F.determinant() > 0.3) return F;
  }
}

// Distance of the HGO fibre invariants from the kink at I = 1 (infinity for other laws).
double kink_distance(const LawCase& c, const Mat3& F) {
  const auto* hgo = dynamic_cast<const HgoLaw*>(c.law.get());
  if (!hgo) return std::numeric_limits<double>::infinity();
  const double i4 = (F * hgo->fibre4(c.frame)).squaredNorm(), i6 = (F * hgo->fibre6(c.frame)).squaredNorm();
  return std::min(std::abs(i4 - 1.0), std::abs(i6 - 1.0));
}

bool both_fibres_in_tension(const LawCase& c, const Mat3& F) {
  const auto* hgo = dynamic_cast<const HgoLaw*>(c.law.get());
  return hgo && (F * hgo->fibre4(c.frame)).squaredNorm() > 1.0 &&
         (F * hgo->fibre6(c.frame)).squaredNorm() > 1.0;
}

// Test deformation gradients: 4 near I and 4 far from I (random), plus 2 that stretch the tilted frame's
// circumferential and axial directions (both HGO fibre families in tension). Those within 1e-3 of the
// HGO kink are redrawn (a central difference across the kink measures the jump, not the derivative).
std::vector<Mat3> test_gradients(const LawCase& c, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Mat3> Fs;
  for (int k = 0; k < 8; ++k) {
    Mat3 F;
    do F = random_F(rng, k < 4);
    while (kink_distance(c, F) < 1e-3);
    Fs.push_back(F);
  }
  const MaterialFrame& f = c.frame;
  for (double s : {1.08, 1.3}) {
    // Stretch s along e_theta and e_z, 1/s along e_r, then a rotation and a small random perturbation.
    const Mat3 U = s * (f.circumferential * f.circumferential.transpose() + f.axial * f.axial.transpose()) +
                   (1.0 / s) * f.radial * f.radial.transpose();
    Mat3 B;
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    for (int k = 0; k < 9; ++k) B(k) = uni(rng);
    Fs.push_back(random_rotation(rng) * (U + 0.01 * B));
  }
  return Fs;
}

TEST(HyperelasticLaw, ZeroEnergyAndStressAtRest) {
  // psi(I) = 0 and P(I) = 0 up to rounding: the constants cancel exactly in exact arithmetic, so the
  // tolerance is 1e-12 of the shear modulus (psi and P are both in Pa). The same holds at any rotation R
  // (rest state rotated); a computed rotation is orthogonal only to ~1e-16, times moduli up to ~10 mu,
  // hence 1e-10 mu there.
  std::mt19937_64 rng(3);
  for (const LawCase& c : all_laws()) {
    SCOPED_TRACE(c.label);
    const Mat3 I = Mat3::Identity();
    EXPECT_LE(std::abs(c.law->energy_density(I, &c.frame)), 1e-12 * c.mu);
    EXPECT_LE(c.law->first_piola(I, &c.frame).norm(), 1e-12 * c.mu);
    for (int k = 0; k < 3; ++k) {
      const Mat3 R = random_rotation(rng);
      EXPECT_LE(std::abs(c.law->energy_density(R, &c.frame)), 1e-10 * c.mu);
      EXPECT_LE(c.law->first_piola(R, &c.frame).norm(), 1e-10 * c.mu);
    }
  }
}

TEST(HyperelasticLaw, FirstPiolaMatchesFiniteDifferenceOfEnergy) {
  // Central differences of psi in each of the 9 entries of F, step h = 1e-6 (F entries are O(1)):
  // truncation ~h^2 |psi'''| ~ 1e-12 relative, rounding ~1e-16 |psi| / h ~ 1e-10 relative, so the
  // required 1e-6 relative error (Frobenius norm) leaves a wide margin yet catches any wrong term.
  const double h = 1e-6;
  int fibre_cases = 0;
  for (const LawCase& c : all_laws()) {
    SCOPED_TRACE(c.label);
    double worst = 0.0;
    for (const Mat3& F : test_gradients(c, 17)) {
      Mat3 P_fd;
      for (int k = 0; k < 9; ++k) {
        Mat3 Fp = F, Fm = F;
        Fp(k) += h;
        Fm(k) -= h;
        P_fd(k) = (c.law->energy_density(Fp, &c.frame) - c.law->energy_density(Fm, &c.frame)) / (2.0 * h);
      }
      const double e = rel_err(c.law->first_piola(F, &c.frame), P_fd);
      worst = std::max(worst, e);
      EXPECT_LE(e, 1e-6) << "F =\n" << F;
      if (both_fibres_in_tension(c, F)) ++fibre_cases;
    }
    record("fd_P_rel_err_" + c.label, worst);
  }
  EXPECT_GE(fibre_cases, 2);  // the HGO fibre terms were exercised in tension
}

TEST(HyperelasticLaw, PiolaDerivativeMatchesFiniteDifferenceOfPiola) {
  // dP(F, dF) against (P(F + h dF) - P(F - h dF)) / (2h), h = 1e-6, |dF| = O(1): same error budget as
  // above, tolerance 1e-6 relative. Also the major symmetry of the elasticity tensor,
  // dF2 : dP(F, dF1) = dF1 : dP(F, dF2), which holds to rounding (1e-10 relative to |dP| |dF|).
  const double h = 1e-6;
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (const LawCase& c : all_laws()) {
    SCOPED_TRACE(c.label);
    double worst = 0.0;
    for (const Mat3& F : test_gradients(c, 29)) {
      Mat3 dF1, dF2;
      for (int k = 0; k < 9; ++k) dF1(k) = uni(rng), dF2(k) = uni(rng);
      const Mat3 dP_fd =
          (c.law->first_piola(F + h * dF1, &c.frame) - c.law->first_piola(F - h * dF1, &c.frame)) / (2.0 * h);
      const Mat3 dP1 = c.law->first_piola_derivative(F, dF1, &c.frame);
      const double e = rel_err(dP1, dP_fd);
      worst = std::max(worst, e);
      EXPECT_LE(e, 1e-6) << "F =\n" << F;
      const Mat3 dP2 = c.law->first_piola_derivative(F, dF2, &c.frame);
      const double a = dF2.cwiseProduct(dP1).sum(), b = dF1.cwiseProduct(dP2).sum();
      EXPECT_LE(std::abs(a - b), 1e-10 * dP1.norm() * dF2.norm());
    }
    record("fd_dP_rel_err_" + c.label, worst);
  }
}

TEST(HyperelasticLaw, SmallStrainMatchesLinearElasticity) {
  // F = I + eps H with a symmetric H and eps = 1e-4: P(F)/eps must equal the linear-elastic stress
  // sigma = lambda tr(H) I + 2 mu H of the law's (lambda, mu) within 0.5 %. The geometric and material
  // nonlinearity contributes O(eps) = 1e-4 relative; a wrong Lame mapping (e.g. lambda' = lambda instead
  // of lambda + mu in neo_hookean) would be off by ~mu/lambda ~ 10 %. The tangent at F = I must equal the
  // same sigma to rounding (1e-10 relative). For hgo, H shortens both fibre families (a.Ha < 0), so the
  // fibres are slack and only the ground matrix (mu = c, kappa) responds.
  const double eps = 1e-4;
  for (const LawCase& c : all_laws()) {
    SCOPED_TRACE(c.label);
    const MaterialFrame& f = c.frame;
    // In the frame (e_r, e_theta, e_z): eps_rr = 0.3, eps_thth = -1, eps_zz = 0.2, eps_thz = 0.1,
    // eps_rth = 0.15, eps_rz = -0.05.
    Mat3 Q;
    Q << f.radial, f.circumferential, f.axial;
    Mat3 Hl;
    Hl << 0.3, 0.15, -0.05, 0.15, -1.0, 0.1, -0.05, 0.1, 0.2;
    const Mat3 H = Q * Hl * Q.transpose();
    if (const auto* hgo = dynamic_cast<const HgoLaw*>(c.law.get())) {
      ASSERT_LT(hgo->fibre4(f).dot(H * hgo->fibre4(f)), 0.0);
      ASSERT_LT(hgo->fibre6(f).dot(H * hgo->fibre6(f)), 0.0);
    }
    const Mat3 sigma = c.lambda * H.trace() * Mat3::Identity() + 2.0 * c.mu * H;
    const Mat3 I = Mat3::Identity();
    const double e_secant = rel_err(c.law->first_piola(I + eps * H, &f) / eps, sigma);
    const double e_tangent = rel_err(c.law->first_piola_derivative(I, H, &f), sigma);
    EXPECT_LE(e_secant, 5e-3);
    EXPECT_LE(e_tangent, 1e-10);
    // psi = 1/2 eps^2 H:sigma to the same order.
    const double psi = c.law->energy_density(I + eps * H, &f),
                 psi_lin = 0.5 * eps * eps * H.cwiseProduct(sigma).sum();
    EXPECT_LE(std::abs(psi - psi_lin), 5e-3 * psi_lin);
    EXPECT_NEAR(c.law->small_strain_shear_modulus(), c.mu, 1e-12 * c.mu);
    EXPECT_NEAR(c.law->small_strain_bulk_modulus(), c.lambda + 2.0 * c.mu / 3.0, 1e-12 * c.lambda);
    record("small_strain_rel_err_" + c.label, e_secant);
  }
}

TEST(HyperelasticLaw, RotationInvariance) {
  // Objectivity: psi(R F) = psi(F), P(R F) = R P(F), dP(R F, R dF) = R dP(F, dF) for rotations R (the
  // material frame is referential and is not rotated). Only rounding differs: 1e-12 relative.
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (const LawCase& c : all_laws()) {
    SCOPED_TRACE(c.label);
    for (const Mat3& F : test_gradients(c, 43)) {
      const Mat3 R = random_rotation(rng);
      Mat3 dF;
      for (int k = 0; k < 9; ++k) dF(k) = uni(rng);
      const double psi = c.law->energy_density(F, &c.frame);
      EXPECT_LE(std::abs(c.law->energy_density(R * F, &c.frame) - psi), 1e-12 * std::abs(psi));
      EXPECT_LE(rel_err(c.law->first_piola(R * F, &c.frame), R * c.law->first_piola(F, &c.frame)), 1e-12);
      EXPECT_LE(rel_err(c.law->first_piola_derivative(R * F, R * dF, &c.frame),
                        R * c.law->first_piola_derivative(F, dF, &c.frame)),
                1e-12);
    }
  }
}

TEST(HyperelasticLawNeoHookean, InvertedHasFiniteEnergyAndRestoringForce) {
  // F = diag(1, 1, s) with s = -0.5 (inverted, J = -0.5). Closed form (neo_hookean_law.hpp):
  // d psi/ds = P_33 = (lambda' + mu)(s - 1) < 0 for s < 1, so psi is finite, the force -P_33 > 0 pushes
  // s back towards +1, and psi decreases monotonically along the straight path to F = I.
  // Tolerances: P_33 against the closed form to 1e-12 relative (rounding only).
  const NeoHookeanLaw law({kE, kNu});
  const double mu = shear_modulus(kE, kNu), lambda_p = lame_lambda(kE, kNu) + mu;
  const Mat3 I = Mat3::Identity();
  const Mat3 F = Vec3(1.0, 1.0, -0.5).asDiagonal();
  const double psi0 = law.energy_density(F);
  const Mat3 P = law.first_piola(F);
  EXPECT_TRUE(std::isfinite(psi0));
  EXPECT_GT(psi0, 0.0);
  EXPECT_TRUE(P.allFinite());
  EXPECT_NEAR(P(2, 2), (lambda_p + mu) * (-0.5 - 1.0), 1e-12 * (lambda_p + mu));
  EXPECT_LT(P.cwiseProduct(I - F).sum(), 0.0);  // d psi along the path towards I is negative
  double prev = psi0;
  for (int k = 1; k <= 20; ++k) {
    const double t = k / 20.0;
    const double psi = law.energy_density(F + t * (I - F));
    EXPECT_LT(psi, prev) << "t = " << t;
    prev = psi;
  }
  EXPECT_LE(std::abs(prev), 1e-12 * mu);  // psi(I) = 0
  // The same for a rotated inverted state (the law is objective, so R F is as far from rest as F).
  std::mt19937_64 rng(5);
  const Mat3 R = random_rotation(rng);
  EXPECT_NEAR(law.energy_density(R * F), psi0, 1e-12 * psi0);
  record("inverted_psi_pa", psi0);
}

TEST(HyperelasticLawHgo, CompressedFibresCarryNoStress) {
  // With both fibre invariants I_4, I_6 <= 1 the fibre terms are switched off, so psi, P and dP equal the
  // ground matrix (stable neo-Hookean with mu = c, kappa) exactly: same floating-point operations plus
  // zeros, tolerance 1e-15 relative.
  const HgoLaw law(hgo2000_carotid_media(kHgoBulk));
  const MaterialFrame f = tilted_frame();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::vector<Mat3> Fs;
  // Shortened along e_theta and e_z, lengthened radially, then rotated.
  const Mat3 U = 0.9 * f.circumferential * f.circumferential.transpose() +
                 0.95 * f.axial * f.axial.transpose() + 1.2 * f.radial * f.radial.transpose();
  Fs.push_back(random_rotation(rng) * U);
  while (Fs.size() < 6) {  // random F with both families compressed
    const Mat3 F = random_F(rng, false);
    if ((F * law.fibre4(f)).squaredNorm() < 1.0 && (F * law.fibre6(f)).squaredNorm() < 1.0) Fs.push_back(F);
  }
  for (const Mat3& F : Fs) {
    Mat3 dF;
    for (int k = 0; k < 9; ++k) dF(k) = uni(rng);
    const double psi_g = law.ground().energy(F);
    EXPECT_LE(std::abs(law.energy_density(F, &f) - psi_g), 1e-15 * std::abs(psi_g));
    EXPECT_LE(rel_err(law.first_piola(F, &f), law.ground().first_piola(F)), 1e-15);
    EXPECT_LE(rel_err(law.first_piola_derivative(F, dF, &f), law.ground().first_piola_derivative(F, dF)),
              1e-15);
  }
}

TEST(HyperelasticLawHgo, UniaxialStretchAlongFibreMatchesClosedForm) {
  // beta = 0: both families along e_theta = e_1 (frame: e_z = e_2, e_r = e_3). Isochoric uniaxial stretch
  // F = diag(lam, 1/sqrt(lam), 1/sqrt(lam)) (J = 1, so I_4 = Ib_4 = lam^2 and HGO 2000's isochoric form
  // gives the same fibre stress). Per family: P_f = 2 psi_f'(I_4) (F a) a^T with F a = lam e_1 and
  // psi_f'(I) = k1 (I - 1) exp(k2 (I - 1)^2); two coincident families:
  //   P_f,11 = 4 k1 lam (lam^2 - 1) exp(k2 (lam^2 - 1)^2),   all other entries 0,
  //   Cauchy sigma_f,11 = P_f,11 lam / J = 4 k1 lam^2 (lam^2 - 1) exp(k2 (lam^2 - 1)^2),
  //   psi_f = 2 k1/(2 k2) [exp(k2 (lam^2 - 1)^2) - 1].
  // P_f = P - P_ground. Tolerance 1e-12 relative (rounding; the closed form is evaluated independently).
  HgoParameters p = hgo2000_carotid_media(kHgoBulk);
  p.fibre_angle_deg = 0.0;
  const HgoLaw law(p);
  const MaterialFrame f = make_material_frame(Vec3::UnitY(), Vec3::UnitZ());
  ASSERT_LE((f.circumferential - Vec3::UnitX()).norm(), 1e-15);
  for (double lam : {1.02, 1.1, 1.2, 1.4}) {
    SCOPED_TRACE(lam);
    const Mat3 F = Vec3(lam, 1.0 / std::sqrt(lam), 1.0 / std::sqrt(lam)).asDiagonal();
    const double x = lam * lam - 1.0, ex = std::exp(p.k2 * x * x);
    Mat3 P_expected = Mat3::Zero();
    P_expected(0, 0) = 4.0 * p.k1_pa * lam * x * ex;
    const Mat3 P_f = law.first_piola(F, &f) - law.ground().first_piola(F);
    EXPECT_LE(rel_err(P_f, P_expected), 1e-12);
    const Mat3 sigma_f = P_f * F.transpose() / F.determinant();
    EXPECT_NEAR(sigma_f(0, 0), 4.0 * p.k1_pa * lam * lam * x * ex, 1e-12 * sigma_f(0, 0));
    const double psi_f = law.energy_density(F, &f) - law.ground().energy(F);
    EXPECT_NEAR(psi_f, p.k1_pa / p.k2 * (ex - 1.0), 1e-9 * psi_f);  // difference of O(1e3) numbers
    if (lam == 1.2) record("hgo_uniaxial_sigma_f_pa_at_1.2", sigma_f(0, 0));
  }
}

TEST(HyperelasticLawHgo, FibreStressInWallFrameMatchesClosedForm) {
  // beta = 29 deg, tilted frame with Q = [e_theta, e_z, e_r]; F = Q diag(l_t, l_z, l_r) Q^T. Both families
  // have I = l_t^2 cos^2 b + l_z^2 sin^2 b; their shear parts cancel, so in the frame
  //   Q^T P_f Q = 4 psi_f'(I) diag(l_t cos^2 b, l_z sin^2 b, 0).
  // With an in-plane shear F = Q [[1, g, 0], [0, 1, 0], [0, 0, 1]] Q^T (g = 0.3) only a_4 is stretched:
  //   I_4 = (cos b + g sin b)^2 + sin^2 b > 1,  I_6 = (cos b - g sin b)^2 + sin^2 b < 1,
  // and P_f = 2 psi_f'(I_4) (F a_4) a_4^T. Tolerance 1e-12 relative (rounding).
  const HgoParameters p = hgo2000_carotid_media(kHgoBulk);
  const HgoLaw law(p);
  const MaterialFrame f = tilted_frame();
  Mat3 Q;
  Q << f.circumferential, f.axial, f.radial;
  const double b = p.fibre_angle_deg * std::numbers::pi / 180.0, cb = std::cos(b), sb = std::sin(b);
  auto dpsi = [&](double I) { return p.k1_pa * (I - 1.0) * std::exp(p.k2 * (I - 1.0) * (I - 1.0)); };
  const double lt = 1.15, lz = 1.05, lr = 0.8;
  const Mat3 F = Q * Vec3(lt, lz, lr).asDiagonal() * Q.transpose();
  const double I = lt * lt * cb * cb + lz * lz * sb * sb;
  const Mat3 expected = 4.0 * dpsi(I) * Vec3(lt * cb * cb, lz * sb * sb, 0.0).asDiagonal();
  const Mat3 P_f = law.first_piola(F, &f) - law.ground().first_piola(F);
  EXPECT_LE(rel_err(Q.transpose() * P_f * Q, expected), 1e-12);

  const double g = 0.3;
  Mat3 S;
  S << 1.0, g, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0;
  const Mat3 Fs = Q * S * Q.transpose();
  const double I4 = (cb + g * sb) * (cb + g * sb) + sb * sb, I6 = (cb - g * sb) * (cb - g * sb) + sb * sb;
  ASSERT_GT(I4, 1.0);
  ASSERT_LT(I6, 1.0);
  const Vec3 a4 = law.fibre4(f);
  const Mat3 expected_s = 2.0 * dpsi(I4) * (Fs * a4) * a4.transpose();
  EXPECT_LE(rel_err(law.first_piola(Fs, &f) - law.ground().first_piola(Fs), expected_s), 1e-12);
}

TEST(HyperelasticLawHgo, NeedsFrame) {
  // Calling an anisotropic law without a frame is a caller bug: std::logic_error, not InputError.
  const HgoLaw law(hgo2000_carotid_media(kHgoBulk));
  EXPECT_TRUE(law.needs_frame());
  EXPECT_THROW(law.energy_density(Mat3::Identity()), std::logic_error);
  EXPECT_THROW(law.first_piola(Mat3::Identity()), std::logic_error);
  EXPECT_FALSE(SvkLaw(SvkParameters{}).needs_frame());
}

TEST(HyperelasticLawMooneyRivlin, UndefinedForNonPositiveJ) {
  // Documented choice (mooney_rivlin_law.hpp): psi = +inf, P and dP all NaN, is_defined false, no throw.
  const MooneyRivlinLaw law({0.1e6, 0.05e6, 1e6});
  for (const Mat3& F : {Mat3(Vec3(1.0, 1.0, -0.5).asDiagonal()), Mat3(Vec3(1.0, 1.0, 0.0).asDiagonal())}) {
    EXPECT_FALSE(law.is_defined(F));
    EXPECT_EQ(law.energy_density(F), std::numeric_limits<double>::infinity());
    EXPECT_TRUE(law.first_piola(F).array().isNaN().all());
    EXPECT_TRUE(law.first_piola_derivative(F, Mat3::Identity()).array().isNaN().all());
  }
  EXPECT_TRUE(law.is_defined(Mat3::Identity()));
}

TEST(HyperelasticLawParameters, BadParametersThrowNamingTheParameter) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<std::function<void()>, std::string>> cases = {
      {[] {
         SvkLaw({-1.0, 0.3});
       },
       "'svk': youngs_modulus_pa ="},
      {[] {
         SvkLaw({1e5, 0.5});
       },
       "'svk': poisson_ratio ="},
      {[] {
         NeoHookeanLaw({0.0, 0.3});
       },
       "'neo_hookean': youngs_modulus_pa ="},
      {[nan] {
         NeoHookeanLaw({nan, 0.3});
       },
       "'neo_hookean': youngs_modulus_pa ="},
      {[] {
         NeoHookeanLaw({1e5, 0.6});
       },
       "'neo_hookean': poisson_ratio ="},
      {[] {
         NeoHookeanLaw({1e5, -1.0});
       },
       "'neo_hookean': poisson_ratio ="},
      {[] {
         MooneyRivlinLaw({-1.0, 1.0, 1e6});
       },
       "'mooney_rivlin': c10_pa ="},
      {[] {
         MooneyRivlinLaw({1.0, -1.0, 1e6});
       },
       "'mooney_rivlin': c01_pa ="},
      {[] {
         MooneyRivlinLaw({0.0, 0.0, 1e6});
       },
       "'mooney_rivlin': c10_pa + c01_pa ="},
      {[] {
         MooneyRivlinLaw({1.0, 1.0, -1e6});
       },
       "'mooney_rivlin': bulk_modulus_pa ="},
      {[] {
         HgoLaw({-3e3, 3e4, 2e3, 0.8, 29.0});
       },
       "'hgo': shear_modulus_pa ="},
      {[] {
         HgoLaw({3e3, 0.0, 2e3, 0.8, 29.0});
       },
       "'hgo': bulk_modulus_pa ="},
      {[] {
         HgoLaw({3e3, 3e4, -2e3, 0.8, 29.0});
       },
       "'hgo': k1_pa ="},
      {[] {
         HgoLaw({3e3, 3e4, 2e3, -0.8, 29.0});
       },
       "'hgo': k2 ="},
      {[] {
         HgoLaw({3e3, 3e4, 2e3, 0.8, 90.5});
       },
       "'hgo': fibre_angle_deg ="},
      {[] {
         HgoLaw({3e3, 3e4, 2e3, 0.8, -1.0});
       },
       "'hgo': fibre_angle_deg ="},
      {[] {
         make_hyperelastic_law("hgo", {{"shear_modulus_pa", 3e3},
                                       {"bulk_modulus_pa", 3e4},
                                       {"k1_pa", 2e3},
                                       {"k2", -1.0},
                                       {"fibre_angle_deg", 29.0}});
       },
       "'hgo': k2 ="},
      {[] {
         make_hyperelastic_law("svk", {{"youngs_modulus_pa", 1e5}});
       },
       "missing parameter 'poisson_ratio'"},
      {[] {
         make_hyperelastic_law("svk", {{"youngs_modulus_pa", 1e5}, {"poisson_ratio", 0.3}, {"nu", 0.3}});
       },
       "unknown parameter 'nu'"},
      {[] {
         make_hyperelastic_law("svk", {{"youngs_modulus_pa", "1e5"}, {"poisson_ratio", 0.3}});
       },
       "'youngs_modulus_pa' must be a number"},
      {[] { make_hyperelastic_law("svk", nlohmann::json::array()); }, "must be a JSON object"},
      {[] { make_hyperelastic_law("ogden", nlohmann::json::object()); }, "unknown hyperelastic law 'ogden'"},
  };
  for (const auto& [make, message] : cases) {
    try {
      make();
      ADD_FAILURE() << "no InputError; expected a message containing: " << message;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
  // Edge values that are allowed.
  EXPECT_NO_THROW(HgoLaw({3e3, 3e4, 0.0, 0.0, 0.0}));
  EXPECT_NO_THROW(HgoLaw({3e3, 3e4, 2e3, 0.8, 90.0}));
  EXPECT_NO_THROW(MooneyRivlinLaw({1.0, 0.0, 1e6}));
}

TEST(HyperelasticLawFactory, RoundTripAndSummaryJson) {
  // make_hyperelastic_law(name(), parameters()) rebuilds the same law: identical psi (bitwise, same
  // operations on the same parameters). to_json() has the summary.json fields; its small-strain E and nu
  // reproduce the (E, nu) the svk/neo_hookean laws were built from (1e-12 relative).
  std::mt19937_64 rng(53);
  for (const LawCase& c : all_laws()) {
    SCOPED_TRACE(c.label);
    const auto copy = make_hyperelastic_law(c.law->name(), c.law->parameters());
    EXPECT_EQ(copy->name(), c.law->name());
    const Mat3 F = random_F(rng, false);
    EXPECT_EQ(copy->energy_density(F, &c.frame), c.law->energy_density(F, &c.frame));
    const nlohmann::json j = c.law->to_json();
    EXPECT_EQ(j.at("law"), c.label);
    EXPECT_EQ(j.at("parameters"), c.law->parameters());
    EXPECT_FALSE(j.at("reference").get<std::string>().empty());
    if (c.label == "svk" || c.label == "neo_hookean") {
      EXPECT_NEAR(j.at("small_strain").at("youngs_modulus_pa").get<double>(), kE, 1e-12 * kE);
      EXPECT_NEAR(j.at("small_strain").at("poisson_ratio").get<double>(), kNu, 1e-12);
    }
  }
  EXPECT_EQ(hyperelastic_law_names().size(), 4u);
}

TEST(HyperelasticLawSvk, MatchesPointPrimitiveEnergy) {
  // PointPrimitiveEnergy (SVK, k_v = 0, no stabiliser) on a 5^3 lattice under the affine map x = F X:
  // the patch test gives F_i = F at every node (docs/model/06-gradients.md, to ~1e-15), so its strain energy
  // is psi_SVK(F) sum_i V_i. Tolerance 1e-10 relative (per-node F errors ~1e-14 enter psi linearly).
  const Material m = test::tissue(kE, kNu);
  const Discretization disc(test::lattice(4), m);
  const PointPrimitiveEnergy energy(disc, EnergyOptions{StrainMeasure::GreenHalf, 0.0, 0.0, {}, {}});
  const SvkLaw law({kE, kNu});
  std::mt19937_64 rng(61);
  for (int k = 0; k < 4; ++k) {
    const Mat3 F = random_F(rng, k < 2);
    Vec3Array x(disc.num_nodes());
    for (Index i = 0; i < disc.num_nodes(); ++i) x[i] = F * disc.rest_positions()[i];
    const double expected = law.energy_density(F) * disc.total_volume();
    EXPECT_NEAR(energy.energy(x).strain, expected, 1e-10 * expected);
  }
}

TEST(HyperelasticLaw, MaterialFrameIsOrthonormalAndRightHanded) {
  // e_theta = e_z x e_r, all unit and orthogonal to rounding (1e-15); the radial input need not be
  // orthogonal to the axial one. Degenerate inputs are InputError.
  const MaterialFrame f = make_material_frame(Vec3(0.0, 0.0, 2.0), Vec3(1.0, 0.0, 0.5));
  EXPECT_LE((f.axial - Vec3::UnitZ()).norm(), 1e-15);
  EXPECT_LE((f.radial - Vec3::UnitX()).norm(), 1e-15);
  EXPECT_LE((f.circumferential - Vec3::UnitY()).norm(), 1e-15);
  const MaterialFrame t = tilted_frame();
  Mat3 Q;
  Q << t.radial, t.circumferential, t.axial;
  EXPECT_LE((Q.transpose() * Q - Mat3::Identity()).norm(), 1e-15);
  EXPECT_NEAR(Q.determinant(), 1.0, 1e-15);
  EXPECT_THROW(make_material_frame(Vec3::Zero(), Vec3::UnitX()), InputError);
  EXPECT_THROW(make_material_frame(Vec3::UnitZ(), 3.0 * Vec3::UnitZ()), InputError);
}

}  // namespace
