#include "vascsim/constraints/meshless_strain_constraint.hpp"

#include <array>
#include <cmath>
#include <stdexcept>

namespace vascsim::constraints {

namespace {
constexpr double kSqrt2 = 1.4142135623730950488;
// Mandel rows: (p, q) index pairs and their scale.
constexpr int kRowP[6] = {0, 1, 2, 1, 0, 0};
constexpr int kRowQ[6] = {0, 1, 2, 2, 2, 1};

// J_k = dc/dx_k for gradient vector dk: row r = s_r * 1/2 (dk_q F_:,p + dk_p F_:,q)^T.
Mat63 jacobian_block(const Mat3& F, const Vec3& dk) {
  Mat63 J;
  for (int r = 0; r < 6; ++r) {
    const int p = kRowP[r], q = kRowQ[r];
    const double s = r < 3 ? 1.0 : kSqrt2;
    J.row(r) = (0.5 * s) * (dk[q] * F.col(p) + dk[p] * F.col(q)).transpose();
  }
  return J;
}
}  // namespace

Vec6 mandel(const Mat3& A) {
  Vec6 v;
  v << A(0, 0), A(1, 1), A(2, 2), kSqrt2 * A(1, 2), kSqrt2 * A(0, 2), kSqrt2 * A(0, 1);
  return v;
}

Mat3 unmandel(const Vec6& v) {
  constexpr double r = 1.0 / kSqrt2;
  Mat3 L;
  L << v[0], r * v[5], r * v[4],  //
      r * v[5], v[1], r * v[3],   //
      r * v[4], r * v[3], v[2];
  return L;
}

Mat6 meshless_strain_block(const Mat3& C, const Mat3& D) {
  // tr(L_r C L_s D) = sum over the non-zero entries (a,b,l) of L_r and (c,d,m) of L_s of l m C_bc D_da. L_r
  // has one entry (p,p,1) on a normal row and two, (p,q) and (q,p) with 1/sqrt2, on a shear row: at most four
  // products per matrix entry instead of two 3x3 products (this block dominated the projection's profile).
  struct Entry {
    int a, b;
    double l;
  };
  static constexpr double r = 0.70710678118654752440;
  static constexpr Entry entries[6][2] = {{{0, 0, 1.0}, {0, 0, 0.0}}, {{1, 1, 1.0}, {0, 0, 0.0}},
                                          {{2, 2, 1.0}, {0, 0, 0.0}}, {{1, 2, r}, {2, 1, r}},
                                          {{0, 2, r}, {2, 0, r}},     {{0, 1, r}, {1, 0, r}}};
  Mat6 S;
  for (int i = 0; i < 6; ++i)
    for (int j = i; j < 6; ++j) {
      double v = 0.0;
      for (int e = 0; e < (i < 3 ? 1 : 2); ++e)
        for (int f = 0; f < (j < 3 ? 1 : 2); ++f) {
          const Entry &x = entries[i][e], &y = entries[j][f];
          v += x.l * y.l * C(x.b, y.a) * D(y.b, x.a);
        }
      S(i, j) = S(j, i) = v;
    }
  return S;
}

Mat6 svk_mandel_stiffness(double lame_lambda_pa, double shear_modulus_pa) {
  Mat6 C = 2.0 * shear_modulus_pa * Mat6::Identity();
  C.topLeftCorner<3, 3>().array() += lame_lambda_pa;
  return C;
}

Mat6 meshless_strain_compliance(double lame_lambda_pa, double shear_modulus_pa, double volume_m3) {
  Mat6 A = Mat6::Identity();
  A.topLeftCorner<3, 3>().array() -= lame_lambda_pa / (3.0 * lame_lambda_pa + 2.0 * shear_modulus_pa);
  return A / (2.0 * shear_modulus_pa * volume_m3);
}

double meshless_strain_energy(const Vec6& c, double lame_lambda_pa, double shear_modulus_pa,
                              double volume_m3) {
  const double tr = c[0] + c[1] + c[2];
  return 0.5 * volume_m3 * (lame_lambda_pa * tr * tr + 2.0 * shear_modulus_pa * c.squaredNorm());
}

void meshless_strain_constraint(Index i, std::span<const Index> neighbours, std::span<const Vec3> d,
                                const Vec3& d_self, const Vec3Array& x, MeshlessStrainEval& out) {
  if (neighbours.size() != d.size())
    throw std::invalid_argument("meshless_strain_constraint: neighbours and d must have the same length");
  // F_i = sum_j (x_j - x_i) d_ij^T (docs/model/06-gradients.md); differences keep the rounding small far from
  // the origin.
  const Vec3& xi = x[static_cast<std::size_t>(i)];
  Mat3 F = Mat3::Zero();
  for (std::size_t s = 0; s < neighbours.size(); ++s)
    F.noalias() += (x[static_cast<std::size_t>(neighbours[s])] - xi) * d[s].transpose();
  out.F = F;
  out.c = mandel(0.5 * (F.transpose() * F - Mat3::Identity()));
  out.nodes.resize(neighbours.size() + 1);
  out.J.resize(neighbours.size() + 1);
  out.nodes[0] = i;
  out.J[0] = jacobian_block(F, d_self);
  for (std::size_t s = 0; s < neighbours.size(); ++s) {
    out.nodes[s + 1] = neighbours[s];
    out.J[s + 1] = jacobian_block(F, d[s]);
  }
}

}  // namespace vascsim::constraints
