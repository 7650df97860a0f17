#pragma once
// Vessel centre-lines: a C1 curve through a polyline of points, parametrised by arc length, with
// rotation-minimising frames (RMF) for sweeping a cross-section along it.
//
// Curve: one cubic Hermite segment between consecutive points. The unit tangent at every point is
// given (factories: exact) or estimated (Bessel / chord-weighted Catmull-Rom; one-sided at the ends).
// The tangent length of a segment is chord / cos^2(phi/4), phi the angle between its end tangents,
// which reproduces a circular arc to O(phi^6) and a straight segment exactly.
// Arc length: 5-point Gauss-Legendre on kSamplesPerSegment sub-intervals, inverted by Newton.
// Frames: double reflection (Wang, Juettler, Zheng, Liu 2008) over the same samples, then one more
// double reflection from the nearest sample below s, so frame(s) is defined for every s.

#include <vector>

#include "vascsim/core/types.hpp"

namespace vascsim {

/// Orthonormal right-handed frame: T tangent, N and B spanning the normal plane, B = T x N.
struct Frame {
  Vec3 T = Vec3::UnitZ();
  Vec3 N = Vec3::UnitX();
  Vec3 B = Vec3::UnitY();
};

class Centerline {
 public:
  /// Through `points` (m), tangents estimated. Throws InputError for < 2 points, non-finite values,
  /// coincident consecutive points or a cusp (the polyline reverses).
  explicit Centerline(Vec3Array points);
  /// Through `points` with the given tangent directions (any positive length, normalised here).
  Centerline(Vec3Array points, Vec3Array tangents);

  double length() const { return length_; }
  /// Position at arc length s (clamped to [0, length]), m.
  Vec3 position(double s) const;
  /// Unit tangent at arc length s.
  Vec3 tangent(double s) const;
  /// Rotation-minimising frame at arc length s. The frame at s = 0 has N = the coordinate axis least
  /// aligned with T, made orthogonal to T (a centre-line along +z gives N = x, B = y, as make_tube).
  Frame frame(double s) const;
  /// Arc length of the centre-line point nearest to `p` (m): the nearest of the arc-length samples, then a
  /// golden-section search between its neighbours. Where two points are about as near (p on the axis of a
  /// circular arc), the first sample's side wins.
  double closest_arc_length(const Vec3& p) const;
  /// Smallest radius of curvature, sampled at the Gauss and sample points of every segment, m.
  double min_radius_of_curvature() const { return min_radius_of_curvature_; }
  const Vec3Array& points() const { return points_; }

  static constexpr int kSamplesPerSegment = 16;

 private:
  struct Segment {
    Vec3 a, b, c, d;  // H(t) = a + b t + c t^2 + d t^3, t in [0, 1]
  };
  struct Sample {
    int seg = 0;
    double t = 0.0;  // local parameter
    double s = 0.0;  // arc length
    Vec3 x, T, N;    // position, unit tangent, RMF normal
  };
  void build(Vec3Array tangents);
  double speed(int seg, double t) const;
  double arc(int seg, double t0, double t1) const;
  // Segment and local parameter at arc length s; also the index of the sample at or below s.
  void locate(double s, int& seg, double& t, std::size_t& k) const;
  Vec3 eval(int seg, double t) const;
  Vec3 deriv(int seg, double t) const;

  Vec3Array points_;
  std::vector<Segment> segs_;
  std::vector<Sample> samples_;
  double length_ = 0.0;
  double min_radius_of_curvature_ = 0.0;
};

/// Straight centre-line from the origin along +z (the axis of make_tube).
Centerline straight_centerline(double length_m);

/// Straight leg along +z from the origin, a circular arc of `angle_deg` (0, 360) bending towards +x
/// in the x-z plane, a second straight leg along the new direction (legs may be 0). 180 degrees with
/// radius 40 mm is an aortic arch.
Centerline bent_centerline(double radius_of_curvature_m, double angle_deg, double straight_leg_length_m);

/// S shape in the x-z plane: leg, arc of `angle_deg` towards +x, arc of `angle_deg` back towards -x,
/// leg. The end direction is again +z.
Centerline s_centerline(double radius_of_curvature_m, double angle_deg, double straight_leg_length_m);

}  // namespace vascsim
