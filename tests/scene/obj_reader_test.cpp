// The OBJ reader (scene/obj_reader.h) and the "subdiv" shape kind: what is read, and every bad
// input named by file and line (or JSON pointer).
#include <gtest/gtest.h>
#include <gmock/gmock.h>
#include <filesystem>
#include <fstream>
#include "core/error.h"
#include "scene/obj_reader.h"
#include "scene/scene_loader.h"
#include "scene_text.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {
using ::testing::HasSubstr;

const char* kCube = R"(# a cube
v -1 -1 -1
v 1 -1 -1
v -1 1 -1
v 1 1 -1
v -1 -1 1
v 1 -1 1
v -1 1 1
v 1 1 1
vt 0 0
vn 0 0 1
g cube
s 1
f 1/1 3/1 4/1 2/1
f 5/1/1 6/1/1 8/1/1 7/1/1
f 1/1/1 2/1/1 6/1/1 5/1/1
f 3/1 7/1 8/1 4/1
f -8/-1 -4/-1 -2/-1 -6/-1
f 2/1 4/1 8/1 6/1
t crease 2/1/0 0 1 3.5
t corner 2/2/0 6 7 1 10
t hole 1/0/0 5
)";

using test::objError;

TEST(ObjReader, ReadsFacesIndicesAndTags) {
  const ObjMesh m = parseObj(kCube, "cube.obj");
  ASSERT_EQ(m.mesh.positions.size(), 8u);
  ASSERT_EQ(m.mesh.faceSizes.size(), 6u);
  EXPECT_EQ(m.mesh.faceVertices[0], 0);
  EXPECT_EQ(m.mesh.faceVertices[4 * 4], 0);  // -8 of 8 vertices is the first
  EXPECT_EQ(m.faceLine[0], 14);
  ASSERT_EQ(m.mesh.creases.size(), 1u);
  EXPECT_EQ(m.mesh.creases[0].v0, 0);
  EXPECT_EQ(m.mesh.creases[0].v1, 1);
  EXPECT_FLOAT_EQ(m.mesh.creases[0].sharpness, 3.5f);
  ASSERT_EQ(m.mesh.corners.size(), 2u);
  EXPECT_FLOAT_EQ(m.mesh.corners[1].sharpness, 10.0f);
  ASSERT_EQ(m.mesh.holes.size(), 1u);
  EXPECT_EQ(m.mesh.holes[0], 5);
}

TEST(ObjReader, MalformedLinesNameTheLine) {
  EXPECT_THAT(objError("v 1 2\n"), HasSubstr("bad.obj:line 1: a vertex needs 3 coordinates"));
  EXPECT_THAT(objError("v 0 0 0\nv 1 x 2\n"), HasSubstr("bad.obj:line 2: malformed number 'x'"));
  EXPECT_THAT(objError("v 0 0 0\nv 1 1e99 2\n"), HasSubstr("line 2"));
  EXPECT_THAT(objError("v 0 0 0\nv 1 0 0\nf 1 2\n"), HasSubstr("line 3: a face needs at least 3 vertices"));
  EXPECT_THAT(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n"), HasSubstr("line 5: vertex index 4 out of range"));
  EXPECT_THAT(objError("v 0 0 0\nf 1 0 1\n"), HasSubstr("line 2: vertex index 0 is not valid"));
  EXPECT_THAT(objError("v 0 0 0\nf -1 -2 -3\n"), HasSubstr("line 2: relative vertex index -2"));
  EXPECT_THAT(objError("v 0 0 0\nf 1/a 1 1\n"), HasSubstr("line 2: malformed face vertex '1/a'"));
  EXPECT_THAT(objError("curv 0 1\n"), HasSubstr("line 1: unsupported OBJ statement 'curv'"));
  EXPECT_THAT(objError("t crease 2/1/0 0 1\n"), HasSubstr("line 1: tag 'crease' declares 3 arguments but has 2"));
  EXPECT_THAT(objError("t crease 3/1/0 0 1 2 1\n"), HasSubstr("line 1: a crease tag needs pairs"));
  EXPECT_THAT(objError("t crease 2-1-0 0 1 1\n"), HasSubstr("line 1: malformed tag header"));
  EXPECT_THAT(objError("t smooth 0/0/0\n"), HasSubstr("line 1: unsupported tag 'smooth'"));
}

TEST(ObjReader, MissingFileIsNamed) {
  try {
    loadObj("/nonexistent/x.obj");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.message(), HasSubstr("/nonexistent/x.obj: cannot open OBJ file"));
  }
}

// The "subdiv" shape in a scene, with its OBJ in a temporary directory.
class SubdivScene : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& text) { return temp_.write(name, text); }
  std::string scene(const std::string& shape) {
    return R"({
  "camera": {"position": [0, -6, 1], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov": 40},
  "film": {"resolution": [32, 24], "spp": 1},
  "materials": {"m": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
  "shapes": [)" + shape + R"(]
})";
  }
  std::string errorOf(const std::string& shape) {
    try {
      loadScene(write("s.json", scene(shape)));
    } catch (const InputError& e) {
      return e.message();
    }
    return "no error";
  }
  testing::TempFolder temp_;
  const std::filesystem::path& dir_ = temp_.dir();
};

TEST_F(SubdivScene, FileFormLoads) {
  write("cube.obj", kCube);
  const Scene s = loadScene(write("s.json", scene(R"({"type": "subdiv", "material": "m", "file": "cube.obj"})")));
  EXPECT_EQ(s.leaves.size(), 5u);  // one face is a hole
  EXPECT_STREQ(s.leaves.patch(0)->kind(), "subdiv");
}

TEST_F(SubdivScene, InlineFormAndLoadLoad) {
  const Scene s = loadScene(write("s.json", scene(R"({"type": "subdiv", "material": "m", "scheme": "loop",
      "vertices": [[1,0,0],[-1,0,0],[0,1,0],[0,-1,0],[0,0,1],[0,0,-1]],
      "faces": [[0,2,4],[2,1,4],[1,3,4],[3,0,4],[2,0,5],[1,2,5],[3,1,5],[0,3,5]],
      "creases": [[0, 2, 2.0]], "corners": [[4, 1.0]],
      "transform": [{"scale": 2}]})")));
  EXPECT_EQ(s.leaves.size(), 24u);
}

TEST_F(SubdivScene, TopologyErrorsNameTheObjLine) {
  write("nonedge.obj", std::string(kCube) + "t crease 2/1/0 0 7 1\n");
  EXPECT_THAT(errorOf(R"({"type": "subdiv", "material": "m", "file": "nonedge.obj"})"),
              HasSubstr("nonedge.obj:line 23: no edge joins vertices 0 and 7"));
  write("twice.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 2\n");
  EXPECT_THAT(errorOf(R"({"type": "subdiv", "material": "m", "file": "twice.obj"})"),
              HasSubstr("twice.obj:line 5: the face uses the same vertex twice"));
  write("quads.obj", kCube);
  EXPECT_THAT(errorOf(R"({"type": "subdiv", "material": "m", "file": "quads.obj", "scheme": "loop"})"),
              HasSubstr("quads.obj:line 14: scheme 'loop' needs an all-triangle mesh"));
  write("hole.obj", std::string(kCube) + "t hole 1/0/0 9\n");
  EXPECT_THAT(errorOf(R"({"type": "subdiv", "material": "m", "file": "hole.obj"})"),
              HasSubstr("hole.obj:line 23: hole face index out of range"));
  write("syntax.obj", "v 0 0 0\nv 1 0\n");
  EXPECT_THAT(errorOf(R"({"type": "subdiv", "material": "m", "file": "syntax.obj"})"), HasSubstr("syntax.obj:line 2"));
}

TEST_F(SubdivScene, JsonErrorsNameThePointer) {
  EXPECT_THAT(errorOf(R"({"type": "subdiv", "material": "m", "vertices": [[0,0,0],[1,0,0],[0,1,0]], "faces": [[0,1,3]]})"),
              HasSubstr("/shapes/0/faces/0: vertex index 3 out of range"));
  EXPECT_THAT(errorOf(R"({"type": "subdiv", "material": "m", "file": "x.obj", "scheme": "doo-sabin"})"),
              HasSubstr("unknown scheme 'doo-sabin'"));
  EXPECT_THAT(errorOf(R"({"type": "subdiv", "material": "m"})"), HasSubstr("exactly one of 'file'"));
  EXPECT_THAT(errorOf(R"({"type": "subdiv", "material": "m", "file": "missing.obj"})"), HasSubstr("cannot open file"));
}

}  // namespace
}  // namespace rayes
