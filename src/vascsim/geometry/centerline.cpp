#include "vascsim/geometry/centerline.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {

constexpr std::array<double, 5> kGaussX = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                           0.9061798459386640};
constexpr std::array<double, 5> kGaussW = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                           0.4786286704993665, 0.2369268850561891};

bool finite(const Vec3& v) {
  return v.allFinite();
}

// Double reflection (Wang et al. 2008, Algorithm 1): carries N from (x0, t0) to (x1, t1).
Vec3 double_reflect(const Vec3& x0, const Vec3& t0, const Vec3& n0, const Vec3& x1, const Vec3& t1) {
  const Vec3 v1 = x1 - x0;
  const double c1 = v1.squaredNorm();
  Vec3 rl = n0, tl = t0;
  if (c1 > 0.0) {
    rl = n0 - (2.0 / c1) * v1.dot(n0) * v1;
    tl = t0 - (2.0 / c1) * v1.dot(t0) * v1;
  }
  const Vec3 v2 = t1 - tl;
  const double c2 = v2.squaredNorm();
  Vec3 n1 = c2 > 0.0 ? Vec3(rl - (2.0 / c2) * v2.dot(rl) * v2) : rl;
  // Re-orthonormalise against round-off drift (a no-op to ~1e-16 per step).
  n1 -= n1.dot(t1) * t1;
  return n1.normalized();
}

}  // namespace

Centerline::Centerline(Vec3Array points) : points_(std::move(points)) {
  if (points_.size() < 2) throw InputError("centerline: at least 2 points are needed");
  for (std::size_t i = 0; i < points_.size(); ++i)
    if (!finite(points_[i])) throw InputError(fmt::format("centerline: point {} is not finite", i));
  const std::size_t n = points_.size();
  Vec3Array tangents(n);
  auto chord = [&](std::size_t i) {
    const Vec3 d = points_[i + 1] - points_[i];
    if (!(d.norm() > 1e-12 * (1.0 + points_[i].norm())))
      throw InputError(fmt::format("centerline: points {} and {} coincide", i, i + 1));
    return d;
  };
  tangents[0] = chord(0).normalized();
  tangents[n - 1] = chord(n - 2).normalized();
  for (std::size_t i = 1; i + 1 < n; ++i) {
    // Bessel tangent: chord directions weighted by the opposite chord length.
    const Vec3 d0 = chord(i - 1), d1 = chord(i);
    const Vec3 m = d1.norm() * d0.normalized() + d0.norm() * d1.normalized();
    if (!(m.norm() > 1e-6 * (d0.norm() + d1.norm())))
      throw InputError(fmt::format("centerline: the polyline reverses at point {} (cusp)", i));
    tangents[i] = m.normalized();
  }
  build(std::move(tangents));
}

Centerline::Centerline(Vec3Array points, Vec3Array tangents) : points_(std::move(points)) {
  if (points_.size() < 2) throw InputError("centerline: at least 2 points are needed");
  if (tangents.size() != points_.size())
    throw InputError(fmt::format("centerline: {} tangents for {} points", tangents.size(), points_.size()));
  for (std::size_t i = 0; i < points_.size(); ++i) {
    if (!finite(points_[i]) || !finite(tangents[i]))
      throw InputError(fmt::format("centerline: point or tangent {} is not finite", i));
    if (!(tangents[i].norm() > 0.0)) throw InputError(fmt::format("centerline: tangent {} is zero", i));
    tangents[i].normalize();
  }
  for (std::size_t i = 0; i + 1 < points_.size(); ++i)
    if (!((points_[i + 1] - points_[i]).norm() > 1e-12 * (1.0 + points_[i].norm())))
      throw InputError(fmt::format("centerline: points {} and {} coincide", i, i + 1));
  build(std::move(tangents));
}

void Centerline::build(Vec3Array tangents) {
  const std::size_t n = points_.size();
  segs_.clear();
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Vec3& p0 = points_[i];
    const Vec3& p1 = points_[i + 1];
    const double cosphi = std::clamp(tangents[i].dot(tangents[i + 1]), -1.0, 1.0);
    const double phi = std::acos(cosphi);
    if (phi > 0.75 * std::numbers::pi)
      throw InputError(
          fmt::format("centerline: the tangent turns by {:.1f} deg between points {} and {}; "
                      "add points",
                      phi * 180.0 / std::numbers::pi, i, i + 1));
    const double c4 = std::cos(0.25 * phi);
    const double len = (p1 - p0).norm() / (c4 * c4);
    const Vec3 m0 = len * tangents[i], m1 = len * tangents[i + 1];
    segs_.push_back({p0, m0, 3.0 * (p1 - p0) - 2.0 * m0 - m1, 2.0 * (p0 - p1) + m0 + m1});
  }
  // Arc-length samples and RMF.
  samples_.clear();
  double s = 0.0;
  double kappa_max = 0.0;
  auto curvature = [&](int seg, double t) {
    const Segment& g = segs_[static_cast<std::size_t>(seg)];
    const Vec3 d1 = deriv(seg, t);
    const Vec3 d2 = 2.0 * g.c + 6.0 * t * g.d;
    return d1.cross(d2).norm() / std::pow(d1.norm(), 3);
  };
  const int ns = static_cast<int>(segs_.size());
  for (int g = 0; g < ns; ++g)
    for (int j = 0; j <= kSamplesPerSegment; ++j) {
      if (j == kSamplesPerSegment && g + 1 < ns) break;  // the next segment's t = 0 sample
      const double t = static_cast<double>(j) / kSamplesPerSegment;
      if (!samples_.empty()) {
        const Sample& p = samples_.back();
        s += arc(p.seg, p.t, p.seg == g ? t : 1.0);
      }
      Sample q;
      q.seg = g;
      q.t = t;
      q.s = s;
      q.x = eval(g, t);
      q.T = deriv(g, t).normalized();
      if (samples_.empty()) {
        Eigen::Index axis = 0;
        q.T.cwiseAbs().minCoeff(&axis);
        const Vec3 e = Vec3::Unit(axis);
        q.N = (e - e.dot(q.T) * q.T).normalized();
      } else {
        const Sample& p = samples_.back();
        q.N = double_reflect(p.x, p.T, p.N, q.x, q.T);
      }
      kappa_max = std::max(kappa_max, curvature(g, t));
      if (j < kSamplesPerSegment) {
        const double h = 1.0 / kSamplesPerSegment;
        for (double gx : kGaussX) kappa_max = std::max(kappa_max, curvature(g, t + 0.5 * h * (gx + 1.0)));
      }
      samples_.push_back(q);
    }
  length_ = s;
  min_radius_of_curvature_ = kappa_max > 0.0 ? 1.0 / kappa_max : std::numeric_limits<double>::infinity();
}

Vec3 Centerline::eval(int seg, double t) const {
  const Segment& g = segs_[static_cast<std::size_t>(seg)];
  return g.a + t * (g.b + t * (g.c + t * g.d));
}

Vec3 Centerline::deriv(int seg, double t) const {
  const Segment& g = segs_[static_cast<std::size_t>(seg)];
  return g.b + t * (2.0 * g.c + 3.0 * t * g.d);
}

double Centerline::speed(int seg, double t) const {
  return deriv(seg, t).norm();
}

double Centerline::arc(int seg, double t0, double t1) const {
  const double h = 0.5 * (t1 - t0), m = 0.5 * (t1 + t0);
  double sum = 0.0;
  for (std::size_t i = 0; i < kGaussX.size(); ++i) sum += kGaussW[i] * speed(seg, m + h * kGaussX[i]);
  return h * sum;
}

void Centerline::locate(double s, int& seg, double& t, std::size_t& k) const {
  if (!std::isfinite(s)) throw InputError("centerline: arc length is not finite");
  s = std::clamp(s, 0.0, length_);
  // Last sample with s_k <= s.
  auto it = std::upper_bound(samples_.begin(), samples_.end(), s,
                             [](double v, const Sample& q) { return v < q.s; });
  k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, (it - samples_.begin()) - 1));
  if (k + 1 >= samples_.size()) k = samples_.size() - 2;
  const Sample& a = samples_[k];
  const Sample& b = samples_[k + 1];
  seg = a.seg;
  const double t1 = b.seg == a.seg ? b.t : 1.0;
  t = a.t + (t1 - a.t) * (s - a.s) / (b.s - a.s);
  for (int iter = 0; iter < 4; ++iter) {  // Newton on arc(a.t, t) = s - s_k; converges quadratically
    const double f = arc(seg, a.t, t) - (s - a.s);
    t = std::clamp(t - f / speed(seg, t), a.t, t1);
  }
}

Vec3 Centerline::position(double s) const {
  int seg = 0;
  double t = 0.0;
  std::size_t k = 0;
  locate(s, seg, t, k);
  return eval(seg, t);
}

double Centerline::closest_arc_length(const Vec3& p) const {
  if (!p.allFinite()) throw InputError("centerline: the point to project is not finite");
  std::size_t nearest = 0;
  for (std::size_t k = 1; k < samples_.size(); ++k)
    if ((samples_[k].x - p).squaredNorm() < (samples_[nearest].x - p).squaredNorm()) nearest = k;
  // The distance is unimodal between the neighbouring samples (a few degrees of turn apart).
  double lo = samples_[nearest == 0 ? 0 : nearest - 1].s;
  double hi = samples_[std::min(nearest + 1, samples_.size() - 1)].s;
  const double inv_phi = (std::sqrt(5.0) - 1.0) / 2.0;
  auto dist2 = [&](double s) { return (position(s) - p).squaredNorm(); };
  double a = hi - inv_phi * (hi - lo), b = lo + inv_phi * (hi - lo);
  double fa = dist2(a), fb = dist2(b);
  while (hi - lo > 1e-12 * std::max(1.0, length_)) {
    if (fa < fb) {
      hi = b, b = a, fb = fa;
      a = hi - inv_phi * (hi - lo), fa = dist2(a);
    } else {
      lo = a, a = b, fa = fb;
      b = lo + inv_phi * (hi - lo), fb = dist2(b);
    }
  }
  return 0.5 * (lo + hi);
}

Vec3 Centerline::tangent(double s) const {
  int seg = 0;
  double t = 0.0;
  std::size_t k = 0;
  locate(s, seg, t, k);
  return deriv(seg, t).normalized();
}

Frame Centerline::frame(double s) const {
  int seg = 0;
  double t = 0.0;
  std::size_t k = 0;
  locate(s, seg, t, k);
  const Sample& a = samples_[k];
  Frame f;
  f.T = deriv(seg, t).normalized();
  f.N = double_reflect(a.x, a.T, a.N, eval(seg, t), f.T);
  f.B = f.T.cross(f.N);
  return f;
}

namespace {

// Builds x-z plane centre-lines from straight legs and circular arcs with exact tangents.
struct PlanarTurtle {
  Vec3Array points{Vec3::Zero()};
  Vec3Array tangents{Vec3::UnitZ()};

  void straight(double len) {
    if (len <= 0.0) return;
    points.push_back(points.back() + len * tangents.back());
    tangents.push_back(tangents.back());
  }
  // Arc bending towards Y x T (sign +1) or away from it (sign -1); <= 1 degree per segment.
  void arc(double radius, double angle_rad, double sign) {
    const Vec3 p0 = points.back(), t0 = tangents.back();
    const Vec3 u = sign * Vec3::UnitY().cross(t0);
    const int n = std::max(2, static_cast<int>(std::ceil(angle_rad / (std::numbers::pi / 180.0) - 1e-9)));
    for (int i = 1; i <= n; ++i) {
      const double a = angle_rad * i / n;
      points.push_back(p0 + radius * (1.0 - std::cos(a)) * u + radius * std::sin(a) * t0);
      tangents.push_back(std::cos(a) * t0 + std::sin(a) * u);
    }
  }
};

void check_bend(const char* who, double radius, double angle_deg, double leg) {
  if (!(std::isfinite(radius) && radius > 0.0))
    throw InputError(fmt::format("{}: radius of curvature must be finite and > 0 (got {})", who, radius));
  if (!(std::isfinite(angle_deg) && angle_deg > 0.0 && angle_deg < 360.0))
    throw InputError(fmt::format("{}: bend angle must be in (0, 360) degrees (got {})", who, angle_deg));
  if (!(std::isfinite(leg) && leg >= 0.0))
    throw InputError(fmt::format("{}: straight leg length must be finite and >= 0 (got {})", who, leg));
}

}  // namespace

Centerline straight_centerline(double length_m) {
  if (!(std::isfinite(length_m) && length_m > 0.0))
    throw InputError(fmt::format("straight centerline: length must be finite and > 0 (got {})", length_m));
  return Centerline({Vec3::Zero(), Vec3(0.0, 0.0, length_m)}, {Vec3::UnitZ(), Vec3::UnitZ()});
}

Centerline bent_centerline(double radius_of_curvature_m, double angle_deg, double straight_leg_length_m) {
  check_bend("bent centerline", radius_of_curvature_m, angle_deg, straight_leg_length_m);
  PlanarTurtle p;
  p.straight(straight_leg_length_m);
  p.arc(radius_of_curvature_m, angle_deg * std::numbers::pi / 180.0, 1.0);
  p.straight(straight_leg_length_m);
  return Centerline(std::move(p.points), std::move(p.tangents));
}

Centerline s_centerline(double radius_of_curvature_m, double angle_deg, double straight_leg_length_m) {
  check_bend("S centerline", radius_of_curvature_m, angle_deg, straight_leg_length_m);
  PlanarTurtle p;
  p.straight(straight_leg_length_m);
  p.arc(radius_of_curvature_m, angle_deg * std::numbers::pi / 180.0, 1.0);
  p.arc(radius_of_curvature_m, angle_deg * std::numbers::pi / 180.0, -1.0);
  p.straight(straight_leg_length_m);
  return Centerline(std::move(p.points), std::move(p.tangents));
}

}  // namespace vascsim
