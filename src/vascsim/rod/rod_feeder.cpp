#include "vascsim/rod/rod_feeder.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include "vascsim/core/error.hpp"

namespace vascsim::rod {

namespace {

// The point at arc length `sigma` along the polyline `x` with cumulative arc lengths `arc`, continued
// straight past either end.
Vec3 along(const Vec3Array& x, const std::vector<double>& arc, double sigma) {
  const std::size_t n = x.size();
  std::size_t j = static_cast<std::size_t>(std::upper_bound(arc.begin(), arc.end(), sigma) - arc.begin());
  j = std::clamp<std::size_t>(j, 1, n - 1);  // the edge (j - 1, j), the end edges continued
  const double f = (sigma - arc[j - 1]) / (arc[j] - arc[j - 1]);
  return x[j - 1] + f * (x[j] - x[j - 1]);
}

}  // namespace

RodFeeder::RodFeeder(CosseratRod& rod, const AccessPort& port, double inserted_m) : rod_(rod), port_(port) {
  if (!(port.axis.norm() > 0.0)) throw InputError("rod: the access port's axis has no direction");
  port_.axis.normalize();
  const RodRestShape& rest = rod.rest_shape();
  s_.assign(1, 0.0);
  for (std::size_t i = 1; i < rest.nodes.size(); ++i)
    s_.push_back(s_.back() + (rest.nodes[i] - rest.nodes[i - 1]).norm());
  const double L = s_.back();
  if (!(inserted_m > 0.0 && inserted_m < L - s_[1]))
    throw InputError(fmt::format("rod: {} m inserted; it must be more than 0 and less than the rod's {} m",
                                 inserted_m, L));
  // The rest shape turned so that its shaft runs along the port's axis, the point at the port on it.
  const Quaternion Q = Quaternion::FromTwoVectors(rest.frames.front() * Vec3::UnitZ(), port_.axis);
  shaft_ = (Q * rest.frames.front()).normalized();
  const Vec3 at_port = along(rest.nodes, s_, L - inserted_m);
  Vec3Array x(rest.nodes.size());
  std::vector<Quaternion> q(rest.frames.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = port_.position_m + Q * (rest.nodes[i] - at_port);
  for (std::size_t j = 0; j < q.size(); ++j) q[j] = (Q * rest.frames[j]).normalized();
  rod_.set_configuration(x, q);
  inserted_ = inserted_m;
  hold();
}

void RodFeeder::drive(double inserted_m, double twist_rad) {
  const double L = s_.back();
  if (!(inserted_m > 0.0 && inserted_m < L - s_[1]) || !std::isfinite(twist_rad))
    throw InputError(fmt::format("rod: {} m inserted; it must be more than 0 and less than the rod's {} m",
                                 inserted_m, L));
  const double feed = inserted_m - inserted_;
  // Every node slides along the current curve by the feed, every frame with its edge; a twist turns each free
  // frame about its own axis (the equilibrium then decides how far the tip turns).
  const Vec3Array x0 = rod_.positions();
  const std::vector<Quaternion> q0 = rod_.frames();
  std::vector<double> arc(1, 0.0);
  for (std::size_t i = 1; i < x0.size(); ++i) arc.push_back(arc.back() + (x0[i] - x0[i - 1]).norm());
  Vec3Array x(x0.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = along(x0, arc, arc[i] + feed);
  std::vector<Quaternion> q(q0.size());
  const Quaternion turn(Eigen::AngleAxisd(twist_rad - twist_, Vec3::UnitZ()));
  for (std::size_t j = 0; j < q.size(); ++j) {
    const double mid = 0.5 * (arc[j] + arc[j + 1]) + feed;
    const std::size_t k = static_cast<std::size_t>(
        std::clamp<std::ptrdiff_t>(std::upper_bound(arc.begin(), arc.end(), mid) - arc.begin() - 1, 0,
                                   static_cast<std::ptrdiff_t>(q0.size()) - 1));
    q[j] = (q0[k] * turn).normalized();
  }
  rod_.set_configuration(x, q);
  inserted_ = inserted_m;
  twist_ = twist_rad;
  hold();
}

void RodFeeder::hold() {
  const double sp = s_.back() - inserted_;
  const Index n = rod_.num_nodes();
  held_.assign(static_cast<std::size_t>(rod_.num_dofs()), 0);
  outside_.assign(static_cast<std::size_t>(n), 0);
  Vec3Array x = rod_.positions();
  std::vector<Quaternion> q = rod_.frames();
  const Quaternion frame = (Quaternion(Eigen::AngleAxisd(twist_, port_.axis)) * shaft_).normalized();
  for (Index i = 0; i < n; ++i) {
    const std::size_t u = static_cast<std::size_t>(i);
    if (s_[u] > sp + 1e-12) continue;
    outside_[u] = 1;
    x[u] = port_.position_m - (sp - s_[u]) * port_.axis;
    for (int a = 0; a < 3; ++a) held_[static_cast<std::size_t>(CosseratRod::position_dof(i) + a)] = 1;
    if (i > 0) {  // edge i - 1 lies wholly behind the port
      q[u - 1] = frame;
      for (int a = 0; a < 3; ++a) held_[static_cast<std::size_t>(rod_.rotation_dof(i - 1) + a)] = 1;
    }
  }
  rod_.set_configuration(x, q);
}

}  // namespace vascsim::rod
