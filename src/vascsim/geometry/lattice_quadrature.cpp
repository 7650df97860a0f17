#include "vascsim/geometry/lattice_quadrature.hpp"

#include <cmath>

#include <fmt/format.h>

#include "vascsim/core/error.hpp"

namespace vascsim {

std::vector<double> cubic_exact_weights(int n) {
  if (n < 2) throw InputError(fmt::format("cubic_exact_weights: {} points; at least 2 are needed", n));
  if (n == 2) return {0.5, 0.5};
  std::vector<double> w(static_cast<std::size_t>(n), 0.0);
  const double h = 1.0 / (n - 1);
  auto add = [&](int k, double c) { w[static_cast<std::size_t>(k)] += c; };
  int start = 0;
  if ((n - 1) % 2 == 1) {  // an odd number of steps: the 3/8 rule on the first three
    const double c = 3.0 * h / 8.0;
    add(0, c), add(1, 3 * c), add(2, 3 * c), add(3, c);
    start = 3;
  }
  for (int k = start; k + 2 < n; k += 2) add(k, h / 3.0), add(k + 1, 4 * h / 3.0), add(k + 2, h / 3.0);
  return w;
}

namespace {
// The factor of the point with index k of n along one layer direction: Simpson weight over trapezoid weight.
double layer_factor(const std::vector<double>& simpson, int k) {
  const int n = static_cast<int>(simpson.size());
  const double trapezoid = (k == 0 || k == n - 1 ? 0.5 : 1.0) / (n - 1);
  return simpson[static_cast<std::size_t>(k)] / trapezoid;
}

int nearest_index(double x, double step, int n, Index node) {
  const int k = static_cast<int>(std::lround(x / step));
  if (k < 0 || k >= n)
    throw InputError(
        fmt::format("Simpson volumes: node {} lies off its lattice (layer {} of {})", node, k, n));
  return k;
}
}  // namespace

std::vector<double> simpson_volume_factors(const Body& body) {
  const NodeCloud& cloud = body.cloud;
  const Index nodes = static_cast<Index>(cloud.positions.size());
  std::vector<double> factor(static_cast<std::size_t>(nodes), 1.0);
  if (body.wall && body.wall->layer_spacing_m > 0.0) {
    const WallCoordinates& w = *body.wall;
    const int layers = static_cast<int>(std::lround(w.thickness_m / w.layer_spacing_m)) + 1;
    const std::vector<double> simpson = cubic_exact_weights(layers);
    for (Index i = 0; i < nodes; ++i)
      factor[static_cast<std::size_t>(i)] = layer_factor(
          simpson, nearest_index(w.depth_m[static_cast<std::size_t>(i)], w.layer_spacing_m, layers, i));
    return factor;
  }
  if ((cloud.box_cells.array() >= 1).all()) {
    const Vec3 step = cloud.box.sizes().cwiseQuotient(cloud.box_cells.cast<double>());
    for (int a = 0; a < 3; ++a) {
      const int n = cloud.box_cells[a] + 1;
      const std::vector<double> simpson = cubic_exact_weights(n);
      for (Index i = 0; i < nodes; ++i) {
        const double x = cloud.positions[static_cast<std::size_t>(i)][a] - cloud.box.min()[a];
        factor[static_cast<std::size_t>(i)] *= layer_factor(simpson, nearest_index(x, step[a], n, i));
      }
    }
    return factor;
  }
  throw InputError(
      "key 'discretization.volume': 'simpson' needs a lattice with node layers (geometry type 'tube', "
      "'vessel', 'box' or 'beam'); use 'tet_partition'");
}

}  // namespace vascsim
