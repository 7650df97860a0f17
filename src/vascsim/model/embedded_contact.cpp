#include "vascsim/model/embedded_contact.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace vascsim {

EmbeddedContact::EmbeddedContact(const ContactSurface& surface, const Vec3Array& rest_nodes_m,
                                 std::size_t tools)
    : surface_(surface), rest_nodes_(rest_nodes_m), geometry_(tools) {
  for (double l1 : surface_.phi_l1) phi_l1_max_ = std::max(phi_l1_max_, l1);
}

bool EmbeddedContact::candidates_hold(const Vec3Array& x) const {
  if (candidate_x_.size() != x.size() || candidate_geometry_.size() != geometry_.size()) return false;
  // The signed distance to a capsule changes by at most how far its segment's ends and its radius moved.
  for (std::size_t o = 0; o < geometry_.size(); ++o) {
    const constraints::Capsule &g = geometry_[o], &c = candidate_geometry_[o];
    const double moved = std::max((g.a - c.a).norm(), (g.b - c.b).norm()) + std::abs(g.radius_m - c.radius_m);
    if (!(moved <= candidate_slack_m_)) return false;
  }
  const double slack2 = candidate_slack_m_ * candidate_slack_m_;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!((x[i] - candidate_x_[i]).squaredNorm() <= slack2)) return false;
  return true;
}

void EmbeddedContact::make_candidates(const Vec3Array& x, double u_max) const {
  // A sample at signed distance d from a tool now stays out of it while the tool moves by less than s and its
  // nodes by less than s each (x_v moves by at most phi_l1_v s): the candidates are the samples with
  // d <= (1 + phi_l1_v) s, s a quarter of the thinnest tool's radius, so that the list serves a frame's
  // residuals and line search, and the next frames while a hand moves the tool 0.04-0.2 mm a frame.
  double thinnest = std::numeric_limits<double>::infinity();
  for (const auto& g : geometry_) thinnest = std::min(thinnest, g.radius_m);
  candidate_slack_m_ = 0.25 * thinnest;
  candidate_geometry_ = geometry_;
  candidate_x_ = x;
  // |x_v - S_v| <= phi_l1_v max_i |u_i| and the distance is 1-Lipschitz, so a box round each tool, as far out
  // as any sample can reach, rejects most samples with six comparisons before any distance.
  std::vector<Eigen::AlignedBox3d> boxes;
  boxes.reserve(geometry_.size());
  for (const auto& g : geometry_) {
    const double out = g.radius_m + phi_l1_max_ * (u_max + candidate_slack_m_) + candidate_slack_m_;
    Eigen::AlignedBox3d box(g.a.cwiseMin(g.b), g.a.cwiseMax(g.b));
    box.min().array() -= out;
    box.max().array() += out;
    boxes.push_back(box);
  }
  const Vec3Array& S = surface_.rest_points;
  candidates_.clear();
  for (Index v = 0; v < surface_.num_samples(); ++v) {
    const double phi = surface_.phi_l1[static_cast<std::size_t>(v)];
    bool inside = false;
    for (std::size_t o = 0; !inside && o < geometry_.size(); ++o) inside = boxes[o].contains(S[v]);
    if (!inside) continue;
    const Vec3 xv = sample_position(v, x);
    bool near = false;
    for (std::size_t o = 0; !near && o < geometry_.size(); ++o)
      near = obstacle_contact(geometry_[o], xv).value <= (1.0 + phi) * candidate_slack_m_;
    if (near) candidates_.push_back(v);
  }
}

Vec3 EmbeddedContact::sample_position(Index v, const Vec3Array& x) const {
  Vec3 xv = surface_.rest_points[v];
  for (Index k = surface_.row_start[v]; k < surface_.row_start[v + 1]; ++k) {
    const Index i = surface_.col[static_cast<std::size_t>(k)];
    xv += surface_.val[static_cast<std::size_t>(k)] * (x[i] - rest_nodes_[i]);
  }
  return xv;
}

template <class F>
void EmbeddedContact::for_each_penetration(const Vec3Array& x, F&& f) const {
  if (geometry_.empty()) return;
  if (!candidates_hold(x)) {
    double u_max2 = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i)
      u_max2 = std::max(u_max2, (x[i] - rest_nodes_[i]).squaredNorm());
    make_candidates(x, std::sqrt(u_max2));
  }
  for (Index v : candidates_) {
    const Vec3 xv = sample_position(v, x);
    int deepest = -1;
    constraints::ContactConstraint c;
    for (std::size_t o = 0; o < geometry_.size(); ++o) {
      const auto co = obstacle_contact(geometry_[o], xv);
      if (co.value < 0.0 && (deepest < 0 || co.value < c.value)) c = co, deepest = static_cast<int>(o);
    }
    if (deepest >= 0) f(v, deepest, xv, c);
  }
}

double EmbeddedContact::energy(const Vec3Array& x) const {
  double e = 0.0;
  for_each_penetration(x, [&](Index v, int, const Vec3&, const constraints::ContactConstraint& c) {
    e +=
        0.5 * surface_.stiffness_pa_per_m * surface_.area_m2[static_cast<std::size_t>(v)] * c.value * c.value;
  });
  return e;
}

EmbeddedContact::Contact EmbeddedContact::make_contact(Index v, int o, const Vec3& xv,
                                                       const constraints::ContactConstraint& c) const {
  const double ka = surface_.stiffness_pa_per_m * surface_.area_m2[static_cast<std::size_t>(v)];
  const double depth = -c.value;
  const Vec3& n = c.normal;
  // The distance's curvature: grad^2 d = (I - n n^T - e e^T) / d, e the capsule's axis on its cylinder
  // (0 on the rounded ends), d the distance to the core; the penetrating depth softens the normal stiffness
  // by depth / d along the surface.
  const constraints::Capsule& g = geometry_[static_cast<std::size_t>(o)];
  const Vec3 ab = g.b - g.a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? (xv - g.a).dot(ab) / len2 : 0.0;
  const Vec3 e = t > 0.0 && t < 1.0 ? Vec3(ab / std::sqrt(len2)) : Vec3::Zero();
  const double core = std::max(g.radius_m - depth, 1e-12);
  const Mat3 nn = n * n.transpose();
  const Mat3 K = ka * (nn - (depth / core) * (Mat3::Identity() - nn - e * e.transpose()));
  return {v, o, xv, n, depth, ka * depth * n, K};
}

void EmbeddedContact::linearize(const Vec3Array& x) {
  active_.clear();
  for_each_penetration(x, [&](Index v, int o, const Vec3& xv, const constraints::ContactConstraint& c) {
    active_.push_back(make_contact(v, o, xv, c));
  });
}

void EmbeddedContact::relinearize_carried(const Vec3Array& x) {
  std::vector<Contact> kept;
  kept.reserve(active_.size());
  for (const Contact& old : active_) {
    const Vec3 xv = sample_position(old.sample, x);
    const auto c = obstacle_contact(geometry_[static_cast<std::size_t>(old.tool)], xv);
    if (c.value < 0.0 || c.value <= carried_gap_m_) kept.push_back(make_contact(old.sample, old.tool, xv, c));
  }
  active_ = std::move(kept);
}

void EmbeddedContact::add_forces(Vec3Array& f) const {
  const auto& start = surface_.row_start;
  const auto& col = surface_.col;
  const auto& val = surface_.val;
  for (const Contact& c : active_)
    for (Index k = start[c.sample]; k < start[c.sample + 1]; ++k)
      f[col[static_cast<std::size_t>(k)]] += val[static_cast<std::size_t>(k)] * c.force;
}

void EmbeddedContact::add_hessian_product(const Vec3Array& p, Vec3Array& Hp, bool normal_only) const {
  const auto& start = surface_.row_start;
  const auto& col = surface_.col;
  const auto& val = surface_.val;
  for (const Contact& c : active_) {
    Vec3 pv = Vec3::Zero();
    for (Index k = start[c.sample]; k < start[c.sample + 1]; ++k)
      pv += val[static_cast<std::size_t>(k)] * p[col[static_cast<std::size_t>(k)]];
    const Vec3 hv = normal_only ? Vec3(c.normal.dot(c.stiffness * c.normal) * c.normal.dot(pv) * c.normal)
                                : Vec3(c.stiffness * pv);
    for (Index k = start[c.sample]; k < start[c.sample + 1]; ++k)
      Hp[col[static_cast<std::size_t>(k)]] += val[static_cast<std::size_t>(k)] * hv;
  }
}

std::vector<ObstacleLoad> EmbeddedContact::loads(const std::vector<Vec3>& tool_points) const {
  std::vector<ObstacleLoad> out(geometry_.size());
  for (const Contact& c : active_) {
    ObstacleLoad& l = out[static_cast<std::size_t>(c.tool)];
    l.force_vector_n += c.force;
    l.torque_vector_n_m += (c.position - tool_points.at(static_cast<std::size_t>(c.tool))).cross(c.force);
    ++l.contacts;
  }
  return out;
}

std::vector<ObstacleLoad> EmbeddedContact::reaction_loads(const std::vector<Vec3>& tool_points,
                                                          const Vec3Array& x, const Vec3Array& residual,
                                                          const std::vector<char>& constrained) const {
  std::vector<ObstacleLoad> out = loads(tool_points);
  // The free nodes the samples move, each with each tool's weight on it (|phi_vi| |f_v|), in node order.
  struct Share {
    Index node;
    int tool;
    double weight;
  };
  std::vector<Share> shares;
  for (const Contact& c : active_)
    for (Index k = surface_.row_start[c.sample]; k < surface_.row_start[c.sample + 1]; ++k) {
      const Index i = surface_.col[static_cast<std::size_t>(k)];
      if (!constrained[static_cast<std::size_t>(i)])
        shares.push_back({i, c.tool, std::abs(surface_.val[static_cast<std::size_t>(k)]) * c.force.norm()});
    }
  std::sort(shares.begin(), shares.end(), [](const Share& a, const Share& b) {
    return a.node != b.node ? a.node < b.node : a.tool < b.tool;
  });
  std::vector<double> per_tool(geometry_.size());
  for (std::size_t a = 0; a < shares.size();) {
    const Index i = shares[a].node;
    std::fill(per_tool.begin(), per_tool.end(), 0.0);
    double total = 0.0;
    std::size_t b = a;
    for (; b < shares.size() && shares[b].node == i; ++b) {
      per_tool[static_cast<std::size_t>(shares[b].tool)] += shares[b].weight;
      total += shares[b].weight;
    }
    const Vec3& r = residual[static_cast<std::size_t>(i)];
    for (std::size_t o = 0; o < per_tool.size(); ++o) {
      // (A node touched only by samples at zero depth goes to the first tool that touches it.)
      const double share =
          total > 0.0 ? per_tool[o] / total : (o == static_cast<std::size_t>(shares[a].tool));
      if (share == 0.0) continue;
      out[o].force_vector_n -= share * r;
      out[o].torque_vector_n_m -= share * (x[static_cast<std::size_t>(i)] - tool_points.at(o)).cross(r);
    }
    a = b;
  }
  return out;
}

double EmbeddedContact::squared_force() const {
  std::vector<Vec3> per_tool(geometry_.size(), Vec3::Zero());
  for (const Contact& c : active_) per_tool[static_cast<std::size_t>(c.tool)] += c.force;
  double s = 0.0;
  for (const Vec3& f : per_tool) s += f.squaredNorm();
  return s;
}

}  // namespace vascsim
