#pragma once
// The Kuhn split of a lattice cell into six tetrahedra, shared by the lattice generators (box, tube,
// swept vessel, mesh wall) so that they all produce the same tets for the same cell.

#include <array>
#include <utility>

#include "vascsim/geometry/node_cloud.hpp"

namespace vascsim {

/// The six tetrahedra of the Kuhn split of a unit cell, as corner bit masks (bit a = +1 along lattice
/// axis a). Each is the path 0 -> e_p -> e_p + e_q -> 7 for a permutation (p, q, r) of the axes, so
/// every tet contains the corners 0 and 7 and the split is conforming between neighbouring cells.
inline constexpr std::array<std::array<int, 4>, 6> kKuhnTets = {{
    {0, 1, 3, 7},
    {0, 1, 5, 7},
    {0, 2, 3, 7},
    {0, 2, 6, 7},
    {0, 4, 5, 7},
    {0, 4, 6, 7},
}};

/// Per Kuhn tet: whether corners 2 and 3 must be swapped for a positive volume in lattice coordinates
/// (a right-handed lattice of positive spacing along every axis).
inline std::array<bool, 6> kuhn_needs_swap() {
  std::array<bool, 6> swap{};
  auto corner = [](int m) { return Vec3(m & 1, (m >> 1) & 1, (m >> 2) & 1); };
  for (std::size_t i = 0; i < kKuhnTets.size(); ++i) {
    const auto& t = kKuhnTets[i];
    swap[i] = signed_volume(corner(t[0]), corner(t[1]), corner(t[2]), corner(t[3])) < 0.0;
  }
  return swap;
}

/// kKuhnTets with corners 2 and 3 swapped where needed: positively oriented in lattice coordinates.
inline std::array<std::array<int, 4>, 6> positive_kuhn_tets() {
  const auto swap = kuhn_needs_swap();
  auto tets = kKuhnTets;
  for (std::size_t i = 0; i < tets.size(); ++i)
    if (swap[i]) std::swap(tets[i][2], tets[i][3]);
  return tets;
}

}  // namespace vascsim
