#pragma once
// Reading vessel surface meshes (STL ASCII/binary, OBJ, PLY) through assimp into a TriangleMesh.

#include <filesystem>

#include "vascsim/geometry/triangle_mesh.hpp"

namespace vascsim {

/// Reads every mesh of `file` (.stl ASCII or binary, .obj, .ply; the extension decides, case-insensitive),
/// triangulates polygons, drops point and line primitives, concatenates all meshes (with their scene-graph
/// transforms), merges vertices at identical positions, and multiplies coordinates by `scale_to_m` (file
/// units to m, e.g. 1e-3 for mm; finite, > 0). The result has passed check_mesh(mesh, file, false): it
/// may be open and need not be oriented consistently.
/// Throws InputError "FILE: reason" for a missing, empty, unreadable or unsupported file or a bad mesh.
TriangleMesh import_triangle_mesh(const std::filesystem::path& file, double scale_to_m);

}  // namespace vascsim
