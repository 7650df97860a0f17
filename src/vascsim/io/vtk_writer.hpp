#pragma once
// VTK XML output for ParaView: the node cloud with its virtual tetrahedra as an unstructured grid
// (.vtu, ASCII), and a .pvd collection indexing a time series.

#include <filesystem>
#include <string>
#include <vector>

#include "vascsim/geometry/node_cloud.hpp"

namespace vascsim {

/// Writes positions x (#N, m) with the tets as cells, and point data "displacement" (x - X, m) and any
/// extra 3-vector fields given as (name, values).
void write_vtu(const std::filesystem::path& file, const Vec3Array& X, const Vec3Array& x, const std::vector<Tet>& tets,
               const std::vector<std::pair<std::string, const Vec3Array*>>& extra = {});

/// One entry of a .pvd collection.
struct PvdEntry {
  double time = 0.0;
  std::string file;  ///< relative to the .pvd
};

void write_pvd(const std::filesystem::path& file, const std::vector<PvdEntry>& entries);

}  // namespace vascsim
