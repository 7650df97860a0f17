#include "vascsim/geometry/swept_vessel.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "vascsim/core/error.hpp"
#include "vascsim/geometry/kuhn.hpp"

namespace vascsim {

SweptVessel make_swept_vessel(const Centerline& cl, const SweptVesselSpec& s) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw InputError("swept vessel: " + what);
  };
  require(std::isfinite(s.outer_radius_m) && s.outer_radius_m > 0.0, "outer radius must be finite and > 0");
  require(
      std::isfinite(s.wall_thickness_m) && s.wall_thickness_m > 0.0 && s.wall_thickness_m < s.outer_radius_m,
      "wall thickness must be > 0 and < outer radius");
  require(std::isfinite(s.node_spacing_m) && s.node_spacing_m > 0.0, "node spacing must be finite and > 0");
  require(s.min_layers >= 3, "at least 3 node layers through the wall are needed (MODEL.md decision 2)");
  require(cl.min_radius_of_curvature() > s.outer_radius_m,
          fmt::format("the centre-line's smallest radius of curvature {:.6g} m must exceed the outer radius "
                      "{:.6g} m (the wall would fold over itself)",
                      cl.min_radius_of_curvature(), s.outer_radius_m));
  const double r_in = s.outer_radius_m - s.wall_thickness_m;
  const double r_mid = 0.5 * (r_in + s.outer_radius_m);
  const double L = cl.length();
  const int nr =
      std::max(s.min_layers, static_cast<int>(std::ceil(s.wall_thickness_m / s.node_spacing_m - 1e-9)) + 1);
  const int nt =
      std::max(8, static_cast<int>(std::lround(2.0 * std::numbers::pi * r_mid / s.node_spacing_m)));
  const double nz_real = L / s.node_spacing_m;
  require(static_cast<double>(nr) * nt * (nz_real + 1.0) <= 5e7,
          "more than 5e7 nodes requested (increase node_spacing_m)");
  const int nz = std::max(2, static_cast<int>(std::lround(nz_real)) + 1);

  SweptVessel out;
  out.length_m = L;
  out.radial_layers = nr;
  out.angular_nodes = nt;
  out.axial_nodes = nz;
  NodeCloud& cloud = out.cloud;
  cloud.kind = "swept_vessel";
  cloud.spacing_m = s.node_spacing_m;
  auto id = [&](int ir, int it, int iz) { return static_cast<Index>(ir + nr * ((it % nt) + nt * iz)); };
  cloud.positions.resize(static_cast<std::size_t>(nr) * nt * nz);
  std::vector<double> cos_t(static_cast<std::size_t>(nt)), sin_t(static_cast<std::size_t>(nt));
  for (int it = 0; it < nt; ++it) {
    const double th = 2.0 * std::numbers::pi * it / nt;
    cos_t[static_cast<std::size_t>(it)] = std::cos(th);
    sin_t[static_cast<std::size_t>(it)] = std::sin(th);
  }
  std::vector<Frame> frames(static_cast<std::size_t>(nz));
  for (int iz = 0; iz < nz; ++iz) {
    const double sz = L * iz / (nz - 1);
    const Vec3 c = cl.position(sz);
    const Frame f = cl.frame(sz);
    frames[static_cast<std::size_t>(iz)] = f;
    for (int it = 0; it < nt; ++it) {
      const Vec3 dir = cos_t[static_cast<std::size_t>(it)] * f.N + sin_t[static_cast<std::size_t>(it)] * f.B;
      for (int ir = 0; ir < nr; ++ir) {
        const double r = r_in + s.wall_thickness_m * ir / (nr - 1);
        cloud.positions[static_cast<std::size_t>(id(ir, it, iz))] = c + r * dir;
      }
    }
  }
  // Oriented in lattice coordinates (r, theta, s): the map to space has positive Jacobian wherever
  // r kappa < 1, so orienting there and checking after the mapping never hides an inversion.
  const auto swap = kuhn_needs_swap();
  cloud.tets.reserve(static_cast<std::size_t>(6) * (nr - 1) * nt * (nz - 1));
  const Vec3Array& X = cloud.positions;
  for (int iz = 0; iz + 1 < nz; ++iz)
    for (int it = 0; it < nt; ++it)
      for (int ir = 0; ir + 1 < nr; ++ir) {
        std::array<Index, 8> c;
        for (int m = 0; m < 8; ++m) c[m] = id(ir + (m & 1), it + ((m >> 1) & 1), iz + ((m >> 2) & 1));
        for (std::size_t k = 0; k < kKuhnTets.size(); ++k) {
          const auto& q = kKuhnTets[k];
          Tet tet{c[q[0]], c[q[1]], c[q[2]], c[q[3]]};
          if (swap[k]) std::swap(tet[2], tet[3]);
          const double v = signed_volume(X[tet[0]], X[tet[1]], X[tet[2]], X[tet[3]]);
          if (!(v > 0.0))
            throw InputError(fmt::format(
                "swept vessel: virtual tetrahedron {} (Kuhn tet {} of lattice cell radial {}, angular {}, "
                "axial "
                "{} at s = {:.6g} m) has volume {:.3g} m^3 <= 0 after sweeping; the bend is too tight for "
                "this outer radius and node spacing",
                cloud.tets.size(), k, ir, it, iz, L * iz / (nz - 1), v));
          cloud.tets.push_back(tet);
        }
      }

  // Surface: outer layer (ir = nr-1) then inner layer (ir = 0), shared by the end rings.
  const std::size_t nsurf = static_cast<std::size_t>(nt) * nz;
  out.surface_vertices.resize(2 * nsurf);
  out.normals.resize(2 * nsurf);
  out.uv.resize(2 * nsurf);
  auto outer = [&](int it, int iz) { return static_cast<Index>((it % nt) + nt * iz); };
  auto inner = [&](int it, int iz) { return static_cast<Index>(nsurf) + outer(it, iz); };
  for (int iz = 0; iz < nz; ++iz)
    for (int it = 0; it < nt; ++it) {
      const Frame& f = frames[static_cast<std::size_t>(iz)];
      const Vec3 dir = cos_t[static_cast<std::size_t>(it)] * f.N + sin_t[static_cast<std::size_t>(it)] * f.B;
      const Eigen::Vector2d uv(static_cast<double>(iz) / (nz - 1), static_cast<double>(it) / nt);
      const auto o = static_cast<std::size_t>(outer(it, iz));
      const auto i = static_cast<std::size_t>(inner(it, iz));
      out.surface_vertices[o] = X[static_cast<std::size_t>(id(nr - 1, it, iz))];
      out.surface_vertices[i] = X[static_cast<std::size_t>(id(0, it, iz))];
      // For an RMF sweep dX/ds is parallel to T, so the radial direction is the exact surface normal.
      out.normals[o] = dir;
      out.normals[i] = -dir;
      out.uv[o] = uv;
      out.uv[i] = uv;
    }
  auto& tri = out.triangles;
  tri.reserve(4 * nsurf + 4 * static_cast<std::size_t>(nt));
  for (int iz = 0; iz + 1 < nz; ++iz)
    for (int it = 0; it < nt; ++it) {
      // (theta step) x (s step) points outward: e_theta x T = e_r.
      const Index a = outer(it, iz), b = outer(it + 1, iz), c = outer(it + 1, iz + 1), d = outer(it, iz + 1);
      tri.push_back({a, b, c});
      tri.push_back({a, c, d});
      const Index ai = inner(it, iz), bi = inner(it + 1, iz), ci = inner(it + 1, iz + 1),
                  di = inner(it, iz + 1);
      tri.push_back({ai, ci, bi});
      tri.push_back({ai, di, ci});
    }
  for (int it = 0; it < nt; ++it) {
    // Start ring faces -T, end ring faces +T.
    tri.push_back({outer(it, 0), inner(it, 0), inner(it + 1, 0)});
    tri.push_back({outer(it, 0), inner(it + 1, 0), outer(it + 1, 0)});
    tri.push_back({outer(it, nz - 1), inner(it + 1, nz - 1), inner(it, nz - 1)});
    tri.push_back({outer(it, nz - 1), outer(it + 1, nz - 1), inner(it + 1, nz - 1)});
  }
  return out;
}

}  // namespace vascsim
