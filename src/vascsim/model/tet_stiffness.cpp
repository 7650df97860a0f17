#include "vascsim/model/tet_stiffness.hpp"

namespace vascsim {

Eigen::SparseMatrix<double> linear_tet_stiffness(const Vec3Array& X, const std::vector<Tet>& tets,
                                                 double lambda, double mu) {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(tets.size() * 144);
  for (const Tet& t : tets) {
    Mat3 Dm;
    for (int c = 0; c < 3; ++c) Dm.col(c) = X[t[c + 1]] - X[t[0]];
    const double V = std::abs(Dm.determinant()) / 6.0;
    const Mat3 Dinv = Dm.inverse();  // rows are the shape gradients of vertices 1..3
    std::array<Vec3, 4> g;
    for (int a = 0; a < 3; ++a) g[a + 1] = Dinv.row(a).transpose();
    g[0] = -(g[1] + g[2] + g[3]);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        const Mat3 K = V * (lambda * g[a] * g[b].transpose() + mu * g[b] * g[a].transpose() +
                            mu * g[a].dot(g[b]) * Mat3::Identity());
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) trip.emplace_back(3 * t[a] + r, 3 * t[b] + c, K(r, c));
      }
  }
  const Eigen::Index n = static_cast<Eigen::Index>(X.size()) * 3;
  Eigen::SparseMatrix<double> K(n, n);
  K.setFromTriplets(trip.begin(), trip.end());
  return K;
}

}  // namespace vascsim
