#include "vascsim/model/problem.hpp"

#include <fmt/format.h>

#include "vascsim/core/error.hpp"

namespace vascsim {

Problem::Problem(const PointPrimitiveEnergy& energy, std::vector<Region> regions, const Vec3& gravity_m_s2,
                 std::vector<RigidObstacle> tools)
    : energy_(energy), regions_(std::move(regions)), gravity_(gravity_m_s2), tools_(std::move(tools)) {
  for (const RigidObstacle& t : tools_)
    if (!(t.radius_m > 0.0)) throw InputError(fmt::format("tool '{}': radius_m must be > 0", t.name));
  const Index n = discretization().num_nodes();
  constrained_.assign(n, 0);
  constraint_region_.assign(n, -1);
  for (std::size_t r = 0; r < regions_.size(); ++r) {
    const Region& reg = regions_[r];
    for (Index i : reg.nodes)
      if (i < 0 || i >= n)
        throw InputError(fmt::format("region '{}': node index {} out of range", reg.name, i));
    if (reg.bc == RegionBcType::Force && reg.force_weights.size() != reg.nodes.size())
      throw InputError(fmt::format("region '{}': force weights do not match its nodes", reg.name));
    if (reg.bc != RegionBcType::Fixed && reg.bc != RegionBcType::Displacement) continue;
    for (Index i : reg.nodes) {
      if (constraint_region_[i] >= 0 && constraint_region_[i] != static_cast<int>(r))
        throw InputError(
            fmt::format("regions '{}' and '{}' both prescribe the position of node {}; constrained "
                        "regions must not overlap",
                        regions_[constraint_region_[i]].name, reg.name, i));
      constraint_region_[i] = static_cast<int>(r);
      constrained_[i] = 1;
    }
  }
  for (char c : constrained_) num_constrained_ += c;
}

Vec3 Problem::prescribed_position(Index i, double s) const {
  const Region& reg = regions_[constraint_region_[i]];
  const Vec3& X = discretization().rest_positions()[i];
  return reg.bc == RegionBcType::Displacement ? Vec3(X + s * reg.displacement_m) : X;
}

void Problem::apply_constraints(double s, Vec3Array& x) const {
  for (Index i = 0; i < discretization().num_nodes(); ++i)
    if (constrained_[i]) x[i] = prescribed_position(i, s);
}

void Problem::external_forces(double s, Vec3Array& f) const {
  const auto& m = discretization().masses();
  f.resize(m.size());
  for (std::size_t i = 0; i < m.size(); ++i) f[i] = s * m[i] * gravity_;
  for (const Region& reg : regions_)
    if (reg.bc == RegionBcType::Force)
      for (std::size_t a = 0; a < reg.nodes.size(); ++a)
        f[reg.nodes[a]] += s * reg.force_weights[a] * reg.force_n;
}

std::vector<RegionMeasure> Problem::measure(double s, const Vec3Array& x, const Vec3Array& f_int,
                                            const Vec3Array& f_ext) const {
  const Vec3Array& X = discretization().rest_positions();
  std::vector<RegionMeasure> out(regions_.size());
  for (std::size_t r = 0; r < regions_.size(); ++r) {
    const Region& reg = regions_[r];
    RegionMeasure& m = out[r];
    Vec3 mean_u = Vec3::Zero();
    for (Index i : reg.nodes) {
      mean_u += x[i] - X[i];
      // Constrained nodes: the support force that balances the tissue, -(f_int + f_ext) (static
      // equilibrium; inertia of the driven nodes is neglected). Force regions: the applied load.
      if (reg.bc == RegionBcType::Fixed || reg.bc == RegionBcType::Displacement)
        m.force_vector_n -= f_int[i] + f_ext[i];
    }
    if (reg.bc == RegionBcType::Force) m.force_vector_n = s * reg.force_n;
    if (!reg.nodes.empty()) mean_u /= static_cast<double>(reg.nodes.size());
    const bool has_dir = reg.direction.squaredNorm() > 0.0;
    m.displacement_m = has_dir ? mean_u.dot(reg.direction) : mean_u.norm();
    m.force_n = has_dir ? m.force_vector_n.dot(reg.direction) : m.force_vector_n.norm();
  }
  return out;
}

}  // namespace vascsim
