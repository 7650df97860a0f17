#include "vascsim/render/lumen_caps.hpp"

#include <map>
#include <unordered_map>
#include <utility>

namespace vascsim::render {

std::vector<std::array<std::uint32_t, 3>> lumen_surface(
    const std::vector<std::array<std::uint32_t, 3>>& triangles, const std::vector<std::uint8_t>& outer) {
  std::vector<std::array<std::uint32_t, 3>> lumen;
  if (outer.empty()) return lumen;
  // Directed edges of the inner triangles; an edge without its reverse is on the boundary.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : triangles) {
    if (outer[t[0]] != 0 || outer[t[1]] != 0 || outer[t[2]] != 0) continue;
    lumen.push_back(t);
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  }
  if (lumen.empty()) return lumen;
  // A cap runs along each boundary edge a->b in the opposite direction b->a.
  std::unordered_multimap<std::uint32_t, std::uint32_t> next;
  for (const auto& [edge, count] : directed)
    if (directed.find({edge.second, edge.first}) == directed.end()) next.emplace(edge.second, edge.first);
  while (!next.empty()) {
    auto it = next.begin();
    const std::uint32_t start = it->first;
    std::vector<std::uint32_t> loop{start};
    std::uint32_t current = it->second;
    next.erase(it);
    while (current != start) {
      loop.push_back(current);
      auto n = next.find(current);
      if (n == next.end()) break;  // an open chain (non-manifold input): no cap for it
      current = n->second;
      next.erase(n);
    }
    if (current != start || loop.size() < 3) continue;
    for (std::size_t i = 1; i + 1 < loop.size(); ++i) lumen.push_back({loop[0], loop[i], loop[i + 1]});
  }
  return lumen;
}

}  // namespace vascsim::render
