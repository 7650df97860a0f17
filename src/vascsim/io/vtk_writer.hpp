#pragma once
// VTK XML output for ParaView: the node cloud with its virtual tetrahedra, and the rendered wall
// surface with its triangles, each as an ASCII unstructured grid (.vtu, readable by ParaView, VTK and
// meshio), and a .pvd collection indexing a time series.

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "vascsim/geometry/node_cloud.hpp"

namespace vascsim {

/// Writes positions x (#N, m) with the tets as cells, and point data "displacement" (x - X, m) and any
/// extra 3-vector fields given as (name, values).
void write_vtu(const std::filesystem::path& file, const Vec3Array& X, const Vec3Array& x,
               const std::vector<Tet>& tets,
               const std::vector<std::pair<std::string, const Vec3Array*>>& extra = {});

/// A triangle surface at one output point.
struct SurfaceVtu {
  const Vec3Array* positions = nullptr;              ///< deformed vertices, m
  const Vec3Array* displacements = nullptr;          ///< m (point data "displacement")
  const Vec3Array* normals = nullptr;                ///< unit (point data "normal"); optional
  const std::vector<Eigen::Vector2d>* uv = nullptr;  ///< texture coordinates (point data "uv"); optional
  const std::vector<std::array<Index, 3>>* triangles = nullptr;
  const std::vector<char>* outer = nullptr;  ///< per triangle (cell data "outer", 0/1); optional
};

/// Writes a surface as an unstructured grid of VTK_TRIANGLE cells.
void write_surface_vtu(const std::filesystem::path& file, const SurfaceVtu& surface);

/// One entry of a .pvd collection.
struct PvdEntry {
  double time = 0.0;
  std::string file;  ///< relative to the .pvd
};

void write_pvd(const std::filesystem::path& file, const std::vector<PvdEntry>& entries);

}  // namespace vascsim
