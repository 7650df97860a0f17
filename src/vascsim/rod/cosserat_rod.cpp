#include "vascsim/rod/cosserat_rod.hpp"

#include <fmt/format.h>
#include <cmath>
#include <stdexcept>

#include "vascsim/core/error.hpp"

namespace vascsim::rod {

namespace {

using Mat = Eigen::MatrixXd;

Quaternion pure(const Vec3& v) {
  return Quaternion(0.0, v.x(), v.y(), v.z());
}

// Derivatives of the increment exp(psi) = (cos(|psi|/2), sin(|psi|/2) psi/|psi|) at psi = 0: d/dpsi_k is
// (0, e_k / 2); its conjugate's (0, -e_k / 2); the second derivative d^2/dpsi_k dpsi_m of either is
// (-delta_km / 4, 0).
Quaternion d_increment(int k) {
  return pure(0.5 * Vec3::Unit(k));
}
Quaternion d_increment_conjugate(int k) {
  return pure(-0.5 * Vec3::Unit(k));
}
Quaternion dd_increment(int k, int m) {
  return Quaternion(k == m ? -0.25 : 0.0, 0.0, 0.0, 0.0);
}

Quaternion exp_increment(const Vec3& psi) {
  const double a = psi.norm();
  return a > 0.0 ? Quaternion(Eigen::AngleAxisd(a, psi / a)) : Quaternion::Identity();
}

// Adds a local symmetric matrix `h` over the coordinates `dofs` (each a block of 3) to the triplets.
void add_local(const std::vector<Index>& dofs, const Mat& h, std::vector<Eigen::Triplet<double>>& t) {
  for (std::size_t A = 0; A < dofs.size(); ++A)
    for (std::size_t B = 0; B < dofs.size(); ++B)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          const double v = h(static_cast<Index>(3 * A + a), static_cast<Index>(3 * B + b));
          if (v != 0.0) t.emplace_back(dofs[A] + a, dofs[B] + b, v);
        }
}

// One edge's strain and its derivatives in the local coordinates [x_j, x_j+1, psi_j]: Gamma, J = dGamma (3 x
// 9), and per component a the second derivative S[a] (9 x 9).
struct EdgeStrain {
  Vec3 gamma;
  Eigen::Matrix<double, 3, 9> J;
  Eigen::Matrix<double, 9, 9> S[3];
};

EdgeStrain edge_strain(const Vec3& x0, const Vec3& x1, const Quaternion& q, double l, bool second) {
  EdgeStrain s;
  const Mat3 RT = q.toRotationMatrix().transpose();
  const Vec3 w = RT * (x1 - x0);
  s.gamma = w / l - Vec3::UnitZ();
  Mat3 Gpsi;
  for (int k = 0; k < 3; ++k) Gpsi.col(k) = w.cross(Vec3::Unit(k)) / l;
  s.J.block<3, 3>(0, 0) = -RT / l;
  s.J.block<3, 3>(0, 3) = RT / l;
  s.J.block<3, 3>(0, 6) = Gpsi;
  if (!second) return s;
  const Quaternion W = pure(w);
  for (int a = 0; a < 3; ++a) s.S[a].setZero();
  for (int k = 0; k < 3; ++k)
    for (int m = 0; m < 3; ++m) {
      // d^2 (exp(psi)^* w exp(psi)) / dpsi_k dpsi_m at 0.
      const Quaternion d = Quaternion(
          (dd_increment(k, m) * W).coeffs() + (d_increment_conjugate(k) * W * d_increment(m)).coeffs() +
          (d_increment_conjugate(m) * W * d_increment(k)).coeffs() + (W * dd_increment(k, m)).coeffs());
      for (int a = 0; a < 3; ++a) s.S[a](6 + k, 6 + m) = d.vec()[a] / l;
    }
  // The mixed derivatives: d/de_m of (w x e_k) / l is (R^T e_m) x e_k / l; x_j enters as -e, x_j+1 as +e.
  for (int m = 0; m < 3; ++m)
    for (int k = 0; k < 3; ++k) {
      const Vec3 v = RT.col(m).cross(Vec3::Unit(k)) / l;
      for (int a = 0; a < 3; ++a) {
        s.S[a](m, 6 + k) = s.S[a](6 + k, m) = -v[a];
        s.S[a](3 + m, 6 + k) = s.S[a](6 + k, 3 + m) = v[a];
      }
    }
  return s;
}

// The Darboux vector of frames qa, qc over lbar and its derivatives in [psi_a, psi_c]: J (3 x 6), S[a] (6 x
// 6).
struct BendStrain {
  Vec3 omega;
  Eigen::Matrix<double, 3, 6> J;
  Eigen::Matrix<double, 6, 6> S[3];
};

BendStrain bend_strain(const Quaternion& qa, const Quaternion& qc, double lbar, bool second) {
  BendStrain s;
  Quaternion p = qa.conjugate() * qc;
  // q and -q are one rotation: take the relative rotation's short way.
  if (p.w() < 0.0) p.coeffs() *= -1.0;
  const double f = 2.0 / lbar;
  s.omega = f * p.vec();
  for (int k = 0; k < 3; ++k) {
    s.J.col(k) = f * (d_increment_conjugate(k) * p).vec();
    s.J.col(3 + k) = f * (p * d_increment(k)).vec();
  }
  if (!second) return s;
  for (int a = 0; a < 3; ++a) s.S[a].setZero();
  for (int k = 0; k < 3; ++k)
    for (int m = 0; m < 3; ++m) {
      const Vec3 aa = f * (dd_increment(k, m) * p).vec();
      const Vec3 cc = f * (p * dd_increment(k, m)).vec();
      const Vec3 ac = f * (d_increment_conjugate(k) * p * d_increment(m)).vec();
      for (int a = 0; a < 3; ++a) {
        s.S[a](k, m) = aa[a];
        s.S[a](3 + k, 3 + m) = cc[a];
        s.S[a](k, 3 + m) = s.S[a](3 + m, k) = ac[a];
      }
    }
  return s;
}

}  // namespace

CosseratRod::CosseratRod(const RodRestShape& rest, const RodStiffness& k)
    : rest_(rest), k_(k), x_(rest.nodes), q_(rest.frames) {
  if (rest.frames.empty() || rest.nodes.size() != rest.frames.size() + 1)
    throw InputError(
        fmt::format("rod: {} nodes and {} edge frames; a rod has one frame per edge, at least one",
                    rest.nodes.size(), rest.frames.size()));
  if (!(k.bend_twist_n_m2.minCoeff() > 0.0) || !(k.shear_stretch_n.minCoeff() > 0.0) ||
      !k.bend_twist_n_m2.allFinite() || !k.shear_stretch_n.allFinite())
    throw InputError("rod: every stiffness (EI, GJ, kGA, EA) must be positive");
  for (std::size_t j = 0; j < q_.size(); ++j) {
    l_.push_back((x_[j + 1] - x_[j]).norm());
    if (!(l_.back() > 0.0)) throw InputError(fmt::format("rod: edge {} has no length", j));
    q_[j].normalize();
  }
  for (Index i = 1; i + 1 < num_nodes(); ++i) {
    Bend b;
    b.a = i - 1;
    b.c = i;
    b.lbar = 0.5 * (l_[static_cast<std::size_t>(i - 1)] + l_[static_cast<std::size_t>(i)]);
    b.rest_darboux =
        bend_strain(q_[static_cast<std::size_t>(i - 1)], q_[static_cast<std::size_t>(i)], b.lbar, false)
            .omega;
    bends_.push_back(b);
  }
}

void CosseratRod::set_configuration(const Vec3Array& x, const std::vector<Quaternion>& q) {
  if (x.size() != x_.size() || q.size() != q_.size())
    throw std::invalid_argument("CosseratRod::set_configuration: sizes differ from the rod's");
  x_ = x;
  q_ = q;
  for (auto& f : q_) f.normalize();
}

void CosseratRod::clamp_start(const Quaternion& frame) {
  for (const Bend& b : bends_)
    if (b.start_clamp) throw std::logic_error("CosseratRod: the start is clamped already");
  Bend b;
  b.c = 0;
  b.start_clamp = true;
  b.lbar = 0.5 * l_.front();
  bends_.push_back(b);
  start_clamp_ = frame.normalized();
}

void CosseratRod::clamp_end(const Quaternion& frame) {
  for (const Bend& b : bends_)
    if (b.end_clamp) throw std::logic_error("CosseratRod: the end is clamped already");
  Bend b;
  b.a = num_edges() - 1;
  b.end_clamp = true;
  b.lbar = 0.5 * l_.back();
  bends_.push_back(b);
  end_clamp_ = frame.normalized();
}

void CosseratRod::move_start_clamp(const Quaternion& frame) {
  start_clamp_ = frame.normalized();
}

void CosseratRod::move_end_clamp(const Quaternion& frame) {
  end_clamp_ = frame.normalized();
}

Quaternion CosseratRod::frame_a(const Bend& b) const {
  return b.start_clamp ? start_clamp_ : q_[static_cast<std::size_t>(b.a)];
}

Quaternion CosseratRod::frame_c(const Bend& b) const {
  return b.end_clamp ? end_clamp_ : q_[static_cast<std::size_t>(b.c)];
}

Vec3 CosseratRod::darboux(const Bend& b) const {
  return bend_strain(frame_a(b), frame_c(b), b.lbar, false).omega;
}

double CosseratRod::energy() const {
  double e = 0.0;
  for (Index j = 0; j < num_edges(); ++j) {
    const std::size_t u = static_cast<std::size_t>(j);
    const Vec3 g = edge_strain(x_[u], x_[u + 1], q_[u], l_[u], false).gamma;
    e += 0.5 * l_[u] * g.dot(k_.shear_stretch_n.cwiseProduct(g));
  }
  for (const Bend& b : bends_) {
    const Vec3 d = darboux(b) - b.rest_darboux;
    e += 0.5 * b.lbar * d.dot(k_.bend_twist_n_m2.cwiseProduct(d));
  }
  return e;
}

Eigen::VectorXd CosseratRod::gradient() const {
  Eigen::VectorXd g = Eigen::VectorXd::Zero(num_dofs());
  for (Index j = 0; j < num_edges(); ++j) {
    const std::size_t u = static_cast<std::size_t>(j);
    const EdgeStrain s = edge_strain(x_[u], x_[u + 1], q_[u], l_[u], false);
    const Eigen::Matrix<double, 9, 1> gl = l_[u] * s.J.transpose() * k_.shear_stretch_n.cwiseProduct(s.gamma);
    g.segment<3>(position_dof(j)) += gl.segment<3>(0);
    g.segment<3>(position_dof(j + 1)) += gl.segment<3>(3);
    g.segment<3>(rotation_dof(j)) += gl.segment<3>(6);
  }
  for (const Bend& b : bends_) {
    const BendStrain s = bend_strain(frame_a(b), frame_c(b), b.lbar, false);
    const Vec3 m = k_.bend_twist_n_m2.cwiseProduct(s.omega - b.rest_darboux);
    const Eigen::Matrix<double, 6, 1> gl = b.lbar * s.J.transpose() * m;
    if (!b.start_clamp) g.segment<3>(rotation_dof(b.a)) += gl.segment<3>(0);
    if (!b.end_clamp) g.segment<3>(rotation_dof(b.c)) += gl.segment<3>(3);
  }
  return g;
}

Eigen::SparseMatrix<double> CosseratRod::hessian() const {
  std::vector<Eigen::Triplet<double>> t;
  const Mat3 Cs = k_.shear_stretch_n.asDiagonal(), Cb = k_.bend_twist_n_m2.asDiagonal();
  for (Index j = 0; j < num_edges(); ++j) {
    const std::size_t u = static_cast<std::size_t>(j);
    const EdgeStrain s = edge_strain(x_[u], x_[u + 1], q_[u], l_[u], true);
    const Vec3 sigma = Cs * s.gamma;
    Mat h = s.J.transpose() * Cs * s.J;
    for (int a = 0; a < 3; ++a) h += sigma[a] * s.S[a];
    add_local({position_dof(j), position_dof(j + 1), rotation_dof(j)}, l_[u] * h, t);
  }
  for (const Bend& b : bends_) {
    const BendStrain s = bend_strain(frame_a(b), frame_c(b), b.lbar, true);
    const Vec3 m = Cb * (s.omega - b.rest_darboux);
    Mat h = s.J.transpose() * Cb * s.J;
    for (int a = 0; a < 3; ++a) h += m[a] * s.S[a];
    h *= b.lbar;
    if (b.start_clamp)
      add_local({rotation_dof(b.c)}, h.block<3, 3>(3, 3), t);
    else if (b.end_clamp)
      add_local({rotation_dof(b.a)}, h.block<3, 3>(0, 0), t);
    else
      add_local({rotation_dof(b.a), rotation_dof(b.c)}, h, t);
  }
  Eigen::SparseMatrix<double> H(num_dofs(), num_dofs());
  H.setFromTriplets(t.begin(), t.end());
  return H;
}

void CosseratRod::apply_increment(const Eigen::VectorXd& d, double scale) {
  if (d.size() != num_dofs()) throw std::invalid_argument("CosseratRod::apply_increment: wrong size");
  for (Index i = 0; i < num_nodes(); ++i)
    x_[static_cast<std::size_t>(i)] += scale * d.segment<3>(position_dof(i));
  for (Index j = 0; j < num_edges(); ++j) {
    Quaternion& q = q_[static_cast<std::size_t>(j)];
    q = (q * exp_increment(scale * d.segment<3>(rotation_dof(j)))).normalized();
  }
}

Vec3 CosseratRod::moment(Index bend_point) const {
  const Bend& b = bends_.at(static_cast<std::size_t>(bend_point));
  return k_.bend_twist_n_m2.cwiseProduct(darboux(b) - b.rest_darboux);
}

Vec3 CosseratRod::edge_force(Index edge) const {
  const std::size_t u = static_cast<std::size_t>(edge);
  return k_.shear_stretch_n.cwiseProduct(
      edge_strain(x_.at(u), x_.at(u + 1), q_.at(u), l_.at(u), false).gamma);
}

double CosseratRod::length() const {
  double s = 0.0;
  for (double l : l_) s += l;
  return s;
}

}  // namespace vascsim::rod
