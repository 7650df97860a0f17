// Malformed meshes from the hostile-input reproducers (docs/reliability.md): every one is an InputError
// naming the file and what is wrong, never a crash, an assertion or a hang, and a file that is fine still
// imports. A tetrahedron's four faces in each format, then broken on purpose.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>

#include "support/cli_capture.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/io/mesh_import.hpp"
#include "vascsim/io/ply_check.hpp"

namespace vascsim {
namespace {

namespace fs = std::filesystem;
using test::fresh_test_dir;
using test::write_file;

const std::string kPlyHeader =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
const std::string kPlyVertices = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
const std::string kPlyFaces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

/// The message of the InputError that importing `bytes` as `name` throws ("" if it imports).
std::string import_error(const std::string& name, const std::string& bytes) {
  const fs::path file = fresh_test_dir() / name;
  write_file(file, bytes);
  try {
    import_triangle_mesh(file, 1e-3);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expect_error(const std::string& name, const std::string& bytes, const std::string& part) {
  const std::string message = import_error(name, bytes);
  EXPECT_NE(message.find(name), std::string::npos) << message;
  EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' in '" << message << "'";
}

TEST(MeshImportMalformed, ValidPlyImports) {
  EXPECT_EQ(import_error("ok.ply", kPlyHeader + kPlyVertices + kPlyFaces), "");
}

TEST(MeshImportMalformed, PlyNegativeFaceIndex) {
  expect_error("negative.ply", kPlyHeader + kPlyVertices + "3 0 2 -1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
               "vertex index -1 is outside [0, 4)");
}

TEST(MeshImportMalformed, PlyFaceIndexPastTheEndIsNamedAsSuch) {
  expect_error("past.ply", kPlyHeader + kPlyVertices + "3 0 2 9\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
               "element 'face' item 0 property 'vertex_indices': vertex index 9 is outside [0, 4)");
}

TEST(MeshImportMalformed, PlyBinaryHeaderOverAnAsciiBody) {
  std::string header = kPlyHeader;
  header.replace(header.find("ascii"), 5, "binary_little_endian");
  // Read as binary, the ASCII text gives nonsense numbers: the walk stops at the first impossible one.
  expect_error("binary.ply", header + kPlyVertices + kPlyFaces, "PLY: element '");
}

TEST(MeshImportMalformed, PlyDeclaringFacesItLacks) {
  expect_error("nofaces.ply", kPlyHeader + kPlyVertices,
               "element 'face': 4 items declared, the body ends after 0");
}

TEST(MeshImportMalformed, PlyWithoutEndHeaderReturnsAtOnce) {
  const auto start = std::chrono::steady_clock::now();
  expect_error("noend.ply", "ply\nformat ascii 1.0\nelement vertex 3\n", "no 'end_header' line");
  // Not a timing test: before the check assimp spun forever on this file; a minute means it still does.
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::minutes(1));
}

TEST(MeshImportMalformed, BinaryPlyIsWalkedAsDeclared) {
  // A valid binary file, then the same with a face index past the end.
  std::string header = kPlyHeader;
  header.replace(header.find("ascii"), 5, "binary_little_endian");
  const auto body = [](int last_index) {
    std::string b;
    const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    b.append(reinterpret_cast<const char*>(v), sizeof v);
    const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, last_index}};
    for (const auto& f : faces) {
      b.push_back(3);
      b.append(reinterpret_cast<const char*>(f), sizeof f);
    }
    return b;
  };
  EXPECT_EQ(import_error("ok-binary.ply", header + body(3)), "");
  expect_error("bad-binary.ply", header + body(4), "vertex index 4 is outside [0, 4)");
}

// Found by fuzz_mesh (SIGSEGV in assimp's post-processing): a header with a second format line and a second
// vertex element, and the face list under another name; each is now rejected by the check.
TEST(MeshImportMalformed, PlyHeaderThatAssimpWouldMisread) {
  expect_error("twice.ply",
               "ply\nformat ascii 1.0\nformat ascii 1.0\n" + kPlyHeader.substr(21) + kPlyVertices + kPlyFaces,
               "a second 'format' line");
  std::string two_vertex_elements = kPlyHeader;
  two_vertex_elements.insert(two_vertex_elements.find("element face"),
                             "element vertex 45\nproperty float x\n");
  expect_error("twice-vertex.ply", two_vertex_elements + kPlyVertices + kPlyFaces,
               "a second element 'vertex'");
  std::string renamed = kPlyHeader;
  renamed.replace(renamed.find("vertex_indices"), 14, "vertex_idx");
  expect_error("renamed.ply", renamed + kPlyVertices + kPlyFaces,
               "the face list 'vertex_idx' is not 'vertex_indices'");
  std::string no_z = kPlyHeader;
  no_z.replace(no_z.find("property float z"), 16, "property float w");
  expect_error("no-z.ply", no_z + kPlyVertices + kPlyFaces, "element 'vertex' has no property 'z'");
}

TEST(MeshImportMalformed, ObjWithNanCoordinates) {
  expect_error("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
               "non-finite");
}

TEST(MeshImportMalformed, BinaryStlWithNanCoordinates) {
  // 80-byte header, a count, and per triangle a normal, three corners and a 2-byte attribute.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float tris[4][4][3] = {{{0, 0, 0}, {0, 0, 0}, {0, 1, 0}, {1, 0, 0}},
                               {{0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {0, 0, 1}},
                               {{0, 0, 0}, {0, 0, 0}, {0, 0, 1}, {0, nan, 0}},
                               {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  std::string bytes(80, ' ');
  const std::uint32_t count = 4;
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : tris) {
    bytes.append(reinterpret_cast<const char*>(t), sizeof t);
    bytes.append(2, '\0');
  }
  expect_error("nan.stl", bytes, "STL: triangle 2 has a non-finite coordinate");
  // The same in ASCII.
  expect_error(
      "nan-ascii.stl",
      "solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 nan 0\nendloop\n"
      "endfacet\nendsolid t\n",
      "STL: line 6 has a non-finite coordinate");
}

}  // namespace
}  // namespace vascsim
