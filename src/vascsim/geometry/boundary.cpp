#include "vascsim/geometry/boundary.hpp"

#include <algorithm>
#include <map>

namespace vascsim {

std::vector<Edge> tet_edges(const std::vector<Tet>& tets) {
  std::vector<Edge> e;
  e.reserve(6 * tets.size());
  for (const Tet& t : tets)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) e.push_back({std::min(t[a], t[b]), std::max(t[a], t[b])});
  std::sort(e.begin(), e.end());
  e.erase(std::unique(e.begin(), e.end()), e.end());
  return e;
}

std::vector<Triangle> boundary_faces(const std::vector<Tet>& tets) {
  // Faces opposite each vertex, ordered so that their normal points away from that vertex for a
  // positively oriented tet.
  static constexpr std::array<std::array<int, 3>, 4> kFaces = {{{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};
  std::map<std::array<Index, 3>, std::pair<Triangle, int>> count;
  for (const Tet& t : tets)
    for (const auto& f : kFaces) {
      Triangle tri{t[f[0]], t[f[1]], t[f[2]]};
      std::array<Index, 3> key = tri;
      std::sort(key.begin(), key.end());
      auto [it, inserted] = count.try_emplace(key, tri, 0);
      ++it->second.second;
    }
  std::vector<Triangle> out;
  for (const auto& [key, value] : count)
    if (value.second == 1) out.push_back(value.first);
  return out;
}

std::vector<double> lumped_boundary_area(const Vec3Array& X, const std::vector<Triangle>& faces,
                                         const std::vector<char>& in_set) {
  std::vector<double> area(X.size(), 0.0);
  for (const Triangle& f : faces) {
    if (!in_set[f[0]] || !in_set[f[1]] || !in_set[f[2]]) continue;
    const double a = 0.5 * (X[f[1]] - X[f[0]]).cross(X[f[2]] - X[f[0]]).norm();
    for (Index v : f) area[v] += a / 3.0;
  }
  return area;
}

}  // namespace vascsim
