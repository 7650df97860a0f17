#include "vascsim/model/contact_active_set.hpp"

#include <algorithm>

#include <cmath>

namespace vascsim {

ContactActiveSet::ContactActiveSet(const Problem& problem, const FreeDofs& free, bool tools_meet_nodes)
    : free_(free) {
  const auto n = static_cast<std::size_t>(problem.discretization().num_nodes());
  geometry_.resize(tools_meet_nodes ? problem.tools().size() : 0);
  contact_of_.assign(n, -1);
  normal_.assign(n, Vec3::Zero());
  lambda_.assign(n, 0.0);
}

void ContactActiveSet::filter(Vec3Array& v) const {
  if (geometry_.empty()) return;
  for (Index i : free_.nodes)
    if (contact_of_[i] >= 0) v[i] -= normal_[i].dot(v[i]) * normal_[i];
}

int ContactActiveSet::project(Vec3Array& x, bool add) {
  int added = 0;
  const int no = static_cast<int>(geometry_.size());
  if (no == 0) return 0;
  for (Index i : free_.nodes) {
    int& o = contact_of_[i];
    if (o < 0) {
      if (!add) continue;
      // The deepest penetration, if any.
      double deepest = 0.0;
      for (int k = 0; k < no; ++k) {
        const double c = obstacle_contact(geometry_[k], x[i]).value;
        if (c < deepest) deepest = c, o = k;
      }
      if (o < 0) continue;
      ++added;
    }
    // Onto the surface along the normal (a contact in the active set is held on the surface).
    const auto c = obstacle_contact(geometry_[o], x[i]);
    x[i] -= c.value * c.normal;
    normal_[i] = c.normal;
  }
  return added;
}

void ContactActiveSet::add_curvature(const Vec3Array& x, const Vec3Array& p, Vec3Array& Hp) const {
  // A node held on a curved tool surface by the normal force lambda feels, when it slides by t along the
  // surface, the turn of that force: the Lagrangian's Hessian gains -lambda grad^2 phi, with
  // grad^2 phi = (I - n n^T - e e^T) / d (d the distance to the tool's core, e the capsule axis on the
  // cylindrical part, e = 0 on the rounded ends). Without it Newton converges only linearly.
  for (Index i : free_.nodes) {
    const int o = contact_of_[i];
    if (o < 0) continue;  // both signs: while in the set the contact is bilateral
    const constraints::Capsule& g = geometry_[static_cast<std::size_t>(o)];
    const Vec3 n = normal_[i];
    Vec3 t = p[i] - n.dot(p[i]) * n;
    const Vec3 ab = g.b - g.a;
    const double len2 = ab.squaredNorm();
    if (len2 > 0.0) {
      const double u = (x[i] - g.a).dot(ab) / len2;
      if (u > 0.0 && u < 1.0) {
        const Vec3 e = ab / std::sqrt(len2);
        t -= e.dot(t) * e;
      }
    }
    Hp[i] -= (lambda_[i] / g.radius_m) * t;
  }
}

void ContactActiveSet::update_lambdas(const Vec3Array& r) {
  for (Index i : free_.nodes) lambda_[i] = contact_of_[i] >= 0 ? -r[i].dot(normal_[i]) : 0.0;
}

int ContactActiveSet::release_pulling(const Vec3Array& r) {
  int released = 0;
  for (Index i : free_.nodes)
    if (contact_of_[i] >= 0 && -r[i].dot(normal_[i]) < 0.0) {
      contact_of_[i] = -1;
      ++released;
    }
  return released;
}

std::vector<ObstacleLoad> ContactActiveSet::loads(const Vec3Array& r, const Vec3Array& x,
                                                  const std::vector<Vec3>& tool_points) const {
  std::vector<ObstacleLoad> out(geometry_.size());
  for (Index i : free_.nodes) {
    const int o = contact_of_[i];
    if (o < 0) continue;
    // Equilibrium in the normal direction: r_i + lambda n_i = 0. A frictionless contact only pushes: a node
    // that pulls (lambda < 0, only before the active set has settled: a real-time frame that ended early)
    // carries no load rather than a glue force.
    const Vec3 f = std::max(0.0, -r[i].dot(normal_[i])) * normal_[i];
    ObstacleLoad& load = out[static_cast<std::size_t>(o)];
    load.force_vector_n += f;
    load.torque_vector_n_m += (x[i] - tool_points[static_cast<std::size_t>(o)]).cross(f);
    ++load.contacts;
  }
  return out;
}

int ContactActiveSet::active() const {
  int n = 0;
  for (Index i : free_.nodes) n += contact_of_[i] >= 0 ? 1 : 0;
  return n;
}

int ContactActiveSet::pulling() const {
  int n = 0;
  for (Index i : free_.nodes) n += contact_of_[i] >= 0 && lambda_[i] < 0.0 ? 1 : 0;
  return n;
}

}  // namespace vascsim
