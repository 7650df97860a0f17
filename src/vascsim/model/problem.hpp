#pragma once
// A boundary-value problem on a discretised body: the elastic energy, named node regions with their
// boundary conditions (fixed, prescribed displacement, applied force), gravity, the rigid tools in
// frictionless contact with the tissue (the catheter), and the reaction forces that the supports exert on
// the tissue. All loads scale with one load factor s in [0, 1]
// (load steps for quasi_static, a time ramp for explicit).

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "vascsim/model/contact_surface.hpp"
#include "vascsim/model/point_primitive_energy.hpp"
#include "vascsim/model/rigid_obstacle.hpp"

namespace vascsim {

enum class RegionBcType {
  Probe,         ///< no boundary condition; only reported
  Fixed,         ///< x = X
  Displacement,  ///< x = X + s * displacement (all three components prescribed, rigid translation)
  Force          ///< total force s * force spread over the nodes by the weights
};

struct Region {
  std::string name;
  std::vector<Index> nodes;
  RegionBcType bc = RegionBcType::Probe;
  Vec3 displacement_m = Vec3::Zero();  ///< Displacement: the full displacement at s = 1, m
  Vec3 force_n = Vec3::Zero();         ///< Force: the total force at s = 1, N
  std::vector<double> force_weights;   ///< Force: per node share of force_n, sums to 1
  Vec3 direction = Vec3::Zero();       ///< unit direction for scalar probes (zero: use magnitudes)
  /// Fixed/Displacement: time at which the boundary condition is removed and the nodes move freely
  /// (time-stepping models that support it; infinity: never), s.
  double release_time_s = std::numeric_limits<double>::infinity();
};

/// What a region reports at one output point.
struct RegionMeasure {
  double displacement_m = 0.0;  ///< mean displacement projected on the direction (or its magnitude)
  /// Reaction: the force the supports exert on the tissue (constrained) or the applied force (Force), summed
  /// over the region, N. The names and meanings of summary.json's: force_vector_n the vector, force_n the
  /// scalar.
  Vec3 force_vector_n = Vec3::Zero();
  double force_n = 0.0;  ///< force_vector_n projected on the direction (or its magnitude), N
};

class Problem {
 public:
  /// Throws InputError for a node index out of range, overlapping constrained regions or a tool without a
  /// positive radius.
  Problem(const PointPrimitiveEnergy& energy, std::vector<Region> regions, const Vec3& gravity_m_s2,
          std::vector<RigidObstacle> tools = {});

  const PointPrimitiveEnergy& energy() const { return energy_; }
  const Discretization& discretization() const { return energy_.discretization(); }
  const std::vector<Region>& regions() const { return regions_; }
  const Vec3& gravity() const { return gravity_; }
  /// Rigid tools in frictionless one-sided contact with the nodes, in scene order (moved by the load factor,
  /// or posed by a device through DeviceDrivenModel).
  const std::vector<RigidObstacle>& tools() const { return tools_; }
  /// The wall's surface the tools meet when contact is embedded (docs/model/22-contact.md section 22.5);
  /// null: the tools meet the nodes.
  const ContactSurface* contact_surface() const { return contact_surface_.get(); }
  void set_contact_surface(std::shared_ptr<const ContactSurface> surface) {
    contact_surface_ = std::move(surface);
  }

  /// Per node: true when its position is prescribed (fixed or displacement region).
  const std::vector<char>& constrained() const { return constrained_; }
  Index num_constrained() const { return num_constrained_; }

  /// Prescribed position of constrained node i at load factor s (m). Only for constrained nodes.
  Vec3 prescribed_position(Index i, double s) const;
  /// Sets every constrained node of x to its prescribed position at load factor s.
  void apply_constraints(double s, Vec3Array& x) const;
  /// External forces at load factor s: gravity m_i g and region forces (N), into f (resized).
  void external_forces(double s, Vec3Array& f) const;

  /// Measures every region at load factor s, configuration x, internal forces f_int and external forces
  /// f_ext.
  std::vector<RegionMeasure> measure(double s, const Vec3Array& x, const Vec3Array& f_int,
                                     const Vec3Array& f_ext) const;

 private:
  const PointPrimitiveEnergy& energy_;
  std::vector<Region> regions_;
  Vec3 gravity_;
  std::vector<RigidObstacle> tools_;
  std::shared_ptr<const ContactSurface> contact_surface_;
  std::vector<char> constrained_;
  std::vector<int> constraint_region_;  // region index per constrained node, -1 otherwise
  Index num_constrained_ = 0;
};

}  // namespace vascsim
