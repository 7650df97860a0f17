#include "vascsim/io/mesh_import.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "vascsim/core/error.hpp"
#include "vascsim/io/obj_check.hpp"
#include "vascsim/io/ply_check.hpp"
#include "vascsim/io/stl_check.hpp"

namespace vascsim {

namespace {

// Exact-position vertex key. assimp's JoinIdenticalVertices also compares normals and texture
// coordinates, so STL corners (per-face normals) and OBJ/PLY seams stay split; merging by position
// alone restores the connectivity the topology checks need. -0.0 is folded onto +0.0.
using PositionKey = std::array<std::uint64_t, 3>;
PositionKey key_of(const Vec3& p) {
  return {std::bit_cast<std::uint64_t>(p.x() + 0.0), std::bit_cast<std::uint64_t>(p.y() + 0.0),
          std::bit_cast<std::uint64_t>(p.z() + 0.0)};
}

struct Collector {
  TriangleMesh mesh;
  std::map<PositionKey, Index> index_of;
  std::size_t non_finite = 0;  // NaN positions never compare equal, so they are kept apart

  Index add_vertex(const Vec3& p) {
    if (!p.allFinite()) {
      ++non_finite;
      mesh.vertices.push_back(p);
      return static_cast<Index>(mesh.vertices.size() - 1);
    }
    const auto [it, inserted] = index_of.emplace(key_of(p), static_cast<Index>(mesh.vertices.size()));
    if (inserted) mesh.vertices.push_back(p);
    return it->second;
  }
};

// assimp's scene is checked before use: mesh references, face indices and the depth of the node tree.
void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, Collector& out,
             const std::string& name, int depth = 0) {
  const auto fail = [&](const std::string& why) { throw InputError(name + ": " + why); };
  if (depth > 64) fail("the file's node hierarchy nests deeper than 64 levels");
  const aiMatrix4x4 transform = parent * node.mTransformation;
  for (unsigned i = 0; i < node.mNumMeshes; ++i) {
    if (node.mMeshes[i] >= scene.mNumMeshes || scene.mMeshes[node.mMeshes[i]] == nullptr)
      fail("the file refers to a mesh it does not hold");
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[i]];
    if (mesh.mNumVertices > 0 && mesh.mVertices == nullptr) fail("a mesh without vertex positions");
    std::vector<Index> local(mesh.mNumVertices);
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = transform * mesh.mVertices[v];
      local[v] = out.add_vertex(Vec3(p.x, p.y, p.z));
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines carry no surface
      for (unsigned k = 0; k < 3; ++k)
        if (face.mIndices[k] >= mesh.mNumVertices)
          fail(fmt::format("face {} refers to vertex {}, past the end of its {} vertices", f,
                           face.mIndices[k], mesh.mNumVertices));
      out.mesh.triangles.push_back(
          {local[face.mIndices[0]], local[face.mIndices[1]], local[face.mIndices[2]]});
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c)
    if (node.mChildren[c] != nullptr) collect(scene, *node.mChildren[c], transform, out, name, depth + 1);
}

std::string read_bytes(const std::filesystem::path& file, const std::string& name) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (!in || in.bad()) throw InputError(name + ": cannot read the file");
  return bytes.str();
}

}  // namespace

TriangleMesh import_triangle_mesh(const std::filesystem::path& file, double scale_to_m) {
  const std::string name = file.string();
  auto fail = [&](const std::string& why) { throw InputError(name + ": " + why); };
  if (!(std::isfinite(scale_to_m) && scale_to_m > 0.0))
    fail(fmt::format("scale_to_m must be finite and > 0 (got {})", scale_to_m));
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".stl" && ext != ".obj" && ext != ".ply")
    fail(fmt::format("unsupported mesh format '{}'; supported: .stl (ASCII or binary), .obj, .ply",
                     ext.empty() ? std::string("(no extension)") : ext));
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) fail("no such file");
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) fail("cannot read the file size: " + ec.message());
  if (size == 0) fail("the file is empty");
  // What assimp does not check or hides: the PLY structure (its loader trusts the header), STL numbers (its
  // vertex joining merges a NaN corner into another vertex), OBJ vertex lines (it reads what it can of a
  // number: "nan", "1,5").
  if (ext == ".ply") check_ply(read_bytes(file, name), name);
  if (ext == ".stl") check_stl_numbers(read_bytes(file, name), name);
  if (ext == ".obj") check_obj_vertices(read_bytes(file, name), name);

  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(name, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices);
  if (scene == nullptr) fail(fmt::format("cannot read the mesh ({})", importer.GetErrorString()));
  if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0 || scene->mRootNode == nullptr)
    fail("the file holds no complete mesh");
  Collector out;
  collect(*scene, *scene->mRootNode, aiMatrix4x4(), out, name);
  for (Vec3& v : out.mesh.vertices) v *= scale_to_m;
  check_mesh(out.mesh, name, /*require_closed=*/false);
  return out.mesh;
}

}  // namespace vascsim
