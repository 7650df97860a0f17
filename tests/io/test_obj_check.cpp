// The OBJ vertex-line check (io/obj_check.hpp) on its own: a vertex line whose values are not finite numbers
// is an InputError naming the file, the line and the vertex; every form assimp reads correctly passes.
// Through the importer and the CLI: test_mesh_import_malformed.cpp and
// SceneValidation.BadObjVertexExitsTwoNamingTheLine.

#include <gtest/gtest.h>

#include <string>

#include "vascsim/core/error.hpp"
#include "vascsim/io/obj_check.hpp"

namespace vascsim {
namespace {

/// The message check_obj_vertices throws for `text` as "mesh.obj" ("" if it passes).
std::string obj_check_message(const std::string& text) {
  try {
    check_obj_vertices(text, "mesh.obj");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A tetrahedron whose third vertex (line 4, after a comment line) is `v3`.
std::string obj_tetrahedron(const std::string& v3) {
  return "# a tetrahedron\nv 0 0 0\nv 1 0 0\n" + v3 +
         "\nv 0 0 1\nvn 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
}

TEST(ObjCheck, NonFiniteOrUnreadableValuesNameTheFileLineAndVertex) {
  // Each message is checked whole up to the value: the file, "OBJ", the line (4: the comment is line 1) and
  // the vertex (3: the third "v" line), so a user can go to the line.
  const std::pair<std::string, std::string> cases[] = {
      {"v 0 nan 0", "mesh.obj: OBJ: line 4: vertex 3 has a non-finite value 'nan'"},
      {"v 0 -NaN 0", "mesh.obj: OBJ: line 4: vertex 3 has a non-finite value '-NaN'"},
      {"v inf 0 0", "mesh.obj: OBJ: line 4: vertex 3 has a non-finite value 'inf'"},
      {"v 0 0 1e999", "mesh.obj: OBJ: line 4: vertex 3 has a non-finite value '1e999'"},  // beyond a double
      {"v 0 1,5 0", "mesh.obj: OBJ: line 4: vertex 3 has '1,5', which is not a number"},  // assimp read 1
      {"v 0 0x1 0", "mesh.obj: OBJ: line 4: vertex 3 has '0x1', which is not a number"},  // assimp read 0
      {"v 0 abc 0", "mesh.obj: OBJ: line 4: vertex 3 has 'abc', which is not a number"},
      {"v 0 1",
       "mesh.obj: OBJ: line 4: vertex 3 has 2 values; a vertex line holds x y z, x y z w or x y z r g b"},
      {"v 0 1 0 1 1", "mesh.obj: OBJ: line 4: vertex 3 has 5 values"},
      {"v 0 .5 0", "mesh.obj: OBJ: line 4: vertex 3 has '.5': write a digit before the point (0.5)"},
      {"v 0 1 0 0.5 nan 0.5", "mesh.obj: OBJ: line 4: vertex 3 has a non-finite value 'nan'"},  // a colour
  };
  for (const auto& [line, expected] : cases) {
    SCOPED_TRACE(line);
    const std::string message = obj_check_message(obj_tetrahedron(line));
    EXPECT_EQ(message.rfind(expected, 0), 0u) << message;
  }
}

TEST(ObjCheck, TheLineIsTheFilesLineWhateverTheLineEndsAndContinuations) {
  // CRLF line ends count one line each; a statement continued with a backslash is named by its first line.
  EXPECT_EQ(obj_check_message("v 0 0 0\r\nv 1 0 0\r\n\r\nv 0 nan 0\r\n")
                .rfind("mesh.obj: OBJ: line 4: vertex 3 ", 0),
            0u);
  EXPECT_EQ(
      obj_check_message("v 0 0 \\\n0\nv 1 \\\n0 \\\nnan\n").rfind("mesh.obj: OBJ: line 3: vertex 2 ", 0), 0u);
}

TEST(ObjCheck, WhatAssimpReadsCorrectlyPasses) {
  for (const char* line : {"v 0 1 0", "v\t0\t1\t0", "  v 0 1 0  ", "v 0 1 0 # a comment", "v 0 1 0 2",
                           "v 0 1 0 0.5 0.5 0.5", "v +1 -1 -.5", "v 1e-400 1E3 0.", "v 0 1 \\\n 0"}) {
    SCOPED_TRACE(line);
    EXPECT_EQ(obj_check_message(obj_tetrahedron(line)), "");
  }
  // Other statements are not vertex lines: assimp checks them.
  EXPECT_EQ(obj_check_message("vt nan 0\nvn 0 0 nan\nvp 1\nvertex nan\n# v nan\nf 1 2 3\n"), "");
  EXPECT_EQ(obj_check_message(""), "");
}

}  // namespace
}  // namespace vascsim
