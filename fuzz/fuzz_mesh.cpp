// Fuzz target: the mesh importer (STL, OBJ, PLY through assimp, then the topology checks). The first byte
// picks the format, the rest is the file.
#include "fuzz_support.hpp"
#include "vascsim/io/mesh_import.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const kExtensions[] = {".stl", ".obj", ".ply"};
  const auto file = vascsim::fuzz::write_input(data + 1, size - 1, kExtensions[data[0] % 3]);
  vascsim::fuzz::expect_clean([&] { vascsim::import_triangle_mesh(file, 1e-3); });
  return 0;
}
