// Uv sets in scene files (docs/scene-format.md, "Uv sets"): OBJ vt lines and v/vt indices, inline
// uvs and uv_faces on subdivision shapes, uv corners on Bézier and bilinear patches, the leaves'
// table (scene/leaf_uv_table.h) they end in, a texture's "coordinates", and every bad input named
// by its OBJ line or JSON pointer.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <cmath>
#include "core/box.h"
#include "core/error.h"
#include "scene/obj_reader.h"
#include "scene/scene_loader.h"
#include "scene_text.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {

using ::testing::HasSubstr;

// A unit square in z = 0 as two quads, with a uv seam along x = 0.5: the right quad's uvs are
// shifted by 0.5 in s. Every face gives its corners' texture coordinates.
const char* kTwoQuads = R"(v 0 0 0
v 0.5 0 0
v 1 0 0
v 0 1 0
v 0.5 1 0
v 1 1 0
vt 0 0
vt 0.5 0
vt 0 1
vt 0.5 1
vt 1 0
vt 1.5 0
vt 1 1
vt 1.5 1
f 1/1 2/2 5/4 4/3
f 2/5 3/6 6/8 5/7
)";

using test::objError;

TEST(ObjUvs, VtLinesAndIndicesBecomeTheUvSet) {
  const ObjMesh m = parseObj(kTwoQuads, "q.obj");
  ASSERT_EQ(m.mesh.uvs.size(), 8u);
  EXPECT_EQ(m.mesh.uvs[5][0], 1.5f);
  EXPECT_EQ(m.mesh.uvIndices, (std::vector<int>{0, 1, 3, 2, 4, 5, 7, 6}));
  EXPECT_EQ(m.uvLine[0], 7);
  // Relative indices count back from the vt lines read so far; v/t/n carries them too.
  const ObjMesh r = parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf -3/-3/1 -2/-2/1 -1/-1/1\n", "r.obj");
  EXPECT_EQ(r.mesh.uvIndices, (std::vector<int>{0, 1, 2}));
  // A mesh whose faces give no texture coordinates has no uv set, whatever vt lines it holds.
  const ObjMesh none = parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1//1 2//1 3//1\n", "n.obj");
  EXPECT_TRUE(none.mesh.uvs.empty());
  EXPECT_TRUE(none.mesh.uvIndices.empty());
}

TEST(ObjUvs, BadTextureCoordinatesNameTheLine) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n";
  EXPECT_THAT(objError(tri + "f 1/1 2/1 3/2\n"), HasSubstr("bad.obj:line 5: texture coordinate index 2 out of range"));
  EXPECT_THAT(objError(tri + "f 1/-2 2/1 3/1\n"), HasSubstr("line 5: relative texture coordinate index -2"));
  EXPECT_THAT(objError(tri + "f 1/0 2/1 3/1\n"), HasSubstr("line 5: texture coordinate index 0 is not valid"));
  EXPECT_THAT(objError(tri + "f 1/1 2 3/1\n"), HasSubstr("line 5: some corners of this face have a texture coordinate"));
  EXPECT_THAT(objError(tri + "f 1/1 2/1 3/1\nf 1 3 2\n"), HasSubstr("line 6: this face has no texture coordinate"));
  EXPECT_THAT(objError("vt nan 0\n"), HasSubstr("line 1: number 'nan' is not finite"));
  EXPECT_THAT(objError("vt 0 inf\n"), HasSubstr("line 1: number 'inf' is not finite"));
  EXPECT_THAT(objError("vt 1e39 0\n"), HasSubstr("line 1: number '1e39' is out of range"));
  EXPECT_THAT(objError("vt\n"), HasSubstr("line 1: a texture coordinate needs u"));
  EXPECT_THAT(objError("vt 0 0 0 0\n"), HasSubstr("line 1: a texture coordinate needs u"));
}

// A scene around the given shapes, with a uv-mapped checker material "c" and a plain one "m".
std::string sceneWith(const std::string& shapes, const std::string& coordinates = R"("uv")") {
  return R"({
  "camera": {"position": [0.5, 0.5, 3], "look_at": [0.5, 0.5, 0], "fov": 40},
  "film": {"resolution": [16, 16], "spp": 1},
  "materials": {
    "c": {"type": "diffuse", "albedo": {"type": "checker", "colors": [0.1, 0.9], "scale": 4, "coordinates": )" +
         coordinates + R"(}},
    "m": {"type": "diffuse", "albedo": 0.5}},
  "shapes": [)" + shapes + R"(]
})";
}

class UvScene : public ::testing::Test {
 protected:
  Scene load(const std::string& shapes) { return loadScene(temp_.write("s.json", sceneWith(shapes))); }
  std::string errorOf(const std::string& shapes, const std::string& coordinates = R"("uv")") {
    try {
      loadScene(temp_.write("s.json", sceneWith(shapes, coordinates)));
    } catch (const InputError& e) {
      return e.message();
    }
    return "no error";
  }
  testing::TempFolder temp_;
};

TEST_F(UvScene, ObjUvsReachTheLeavesWithTheSeam) {
  temp_.write("q.obj", kTwoQuads);
  const Scene s = load(R"({"type": "subdiv", "material": "c", "file": "q.obj", "scheme": "bilinear"},
                          {"type": "bilinear", "material": "m", "quads": [[[0,0,-1],[1,0,-1],[0,1,-1],[1,1,-1]]]})");
  ASSERT_EQ(s.leaves.size(), 3u);
  ASSERT_TRUE(s.uvs);
  EXPECT_TRUE(s.uvs->has(0));
  EXPECT_TRUE(s.uvs->has(1));
  EXPECT_FALSE(s.uvs->has(2));  // the plain quad
  EXPECT_FALSE(s.uvs->has(1000));
  // Linear interpolation (the default, OpenSubdiv's "all"): each face's uvs are the bilinear
  // blend of its corners' within the rounding of a blend of 4 values below 1.5.
  const float tol = gammaBound(8) * 1.5f;
  const TexCoordSample left = s.uvs->at(0, 1, 0.5f), right = s.uvs->at(1, 0, 0.5f);
  EXPECT_NEAR(left.s, 0.5f, tol);
  EXPECT_NEAR(right.s, 1.0f, tol);  // across the seam
  EXPECT_NEAR(left.t, right.t, 2 * tol);
  EXPECT_NEAR(left.dsdu, 0.5f, 2 * tol);
  EXPECT_NEAR(left.dtdv, 1.0f, 2 * tol);
  EXPECT_NEAR(left.dtdu, 0.0f, 2 * tol);
  EXPECT_NEAR(left.dsdv, 0.0f, 2 * tol);
  // The material reads uv coordinates.
  const Material& c = s.materials[s.leafMaterial[0]];
  ASSERT_TRUE(c.albedo.texture);
  EXPECT_EQ(c.albedo.texture->coordinates, Texture::Coordinates::Uv);
}

TEST_F(UvScene, ASceneWithoutUvsHasNoTable) {
  const Scene s = load(R"({"type": "bilinear", "material": "c", "quads": [[[0,0,0],[1,0,0],[0,1,0],[1,1,0]]]})");
  EXPECT_FALSE(s.uvs);
  EXPECT_EQ(s.materials[s.leafMaterial[0]].albedo.texture->coordinates, Texture::Coordinates::Uv);
  EXPECT_FALSE(s.uvSetsDropped);
}

TEST_F(UvScene, UvSetsNoTextureReadsAreLeftOut) {
  const std::string shape = R"({"type": "bilinear", "material": "c", "quads": [[[0,0,0],[1,0,0],[0,1,0],[1,1,0]]],
                                "uvs": [[[0,0],[1,0],[0,1],[1,1]]]})";
  const Scene patch = loadScene(temp_.write("p.json", sceneWith(shape, R"("patch")")));
  EXPECT_FALSE(patch.uvs);
  EXPECT_TRUE(patch.uvSetsDropped);
  EXPECT_TRUE(load(shape).uvs);
}

TEST_F(UvScene, InlineUvsPerVertexOrWithTheirOwnIndices) {
  // Per vertex: the same uv set as uv_faces equal to faces.
  const std::string verts = R"("vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]], "faces": [[0,1,2,3]])";
  const Scene a = load(R"({"type": "subdiv", "material": "c", "scheme": "bilinear", )" + verts +
                       R"(, "uvs": [[0,0],[2,0],[2,2],[0,2]]})");
  const Scene b = load(R"({"type": "subdiv", "material": "c", "scheme": "bilinear", )" + verts +
                       R"(, "uvs": [[2,2],[0,2],[0,0],[2,0]], "uv_faces": [[2,3,0,1]], "uv_interpolation": "boundaries"})");
  for (const float u : {0.0f, 0.25f, 1.0f})
    for (const float v : {0.0f, 0.5f, 1.0f}) {
      const TexCoordSample sa = a.uvs->at(0, u, v), sb = b.uvs->at(0, u, v);
      EXPECT_NEAR(sa.s, 2 * u, gammaBound(8) * 2);
      EXPECT_NEAR(sa.t, 2 * v, gammaBound(8) * 2);
      EXPECT_NEAR(sb.s, sa.s, gammaBound(8) * 4);
      EXPECT_NEAR(sb.t, sa.t, gammaBound(8) * 4);
    }
}

TEST_F(UvScene, PatchCornersAreBilinearInUV) {
  const Scene s = load(R"({"type": "bilinear", "material": "c",
      "quads": [[[0,0,0],[1,0,0],[0,1,0],[1,1,0]], [[1,0,0],[2,0,0],[1,1,0],[2,1,0]]],
      "uvs": [[[0,0],[1,0],[0,1],[1,1]], [[1,0],[3,0],[1,1],[2,2]]]},
      {"type": "bezier", "material": "c", "patches": [[
        [0,0,0],[1,0,0],[2,0,0],[3,0,0], [0,1,0],[1,1,0],[2,1,0],[3,1,0],
        [0,2,0],[1,2,0],[2,2,0],[3,2,0], [0,3,0],[1,3,0],[2,3,0],[3,3,0]]],
      "uvs": [[[0.5,0.5],[0.5,0.5],[0.5,0.5],[0.5,0.5]]]})");
  ASSERT_EQ(s.leaves.size(), 3u);
  for (uint32_t leaf = 0; leaf < 3; ++leaf) EXPECT_TRUE(s.uvs->has(leaf));
  // Leaf 1 at (u, v): s = 1 + 2u + (-u v) ... the bilinear blend of (1,0), (3,0), (1,1), (2,2).
  const float u = 0.25f, v = 0.75f;
  const TexCoordSample q = s.uvs->at(1, u, v);
  EXPECT_FLOAT_EQ(q.s, (1 - u) * (1 - v) * 1 + u * (1 - v) * 3 + (1 - u) * v * 1 + u * v * 2);
  EXPECT_FLOAT_EQ(q.t, (1 - u) * v * 1 + u * v * 2);
  EXPECT_FLOAT_EQ(q.dsdu, (1 - v) * 2 + v * 1);
  EXPECT_FLOAT_EQ(q.dsdv, (1 - u) * 0 + u * (2 - 3));
  EXPECT_FLOAT_EQ(q.dtdu, v * 1);
  EXPECT_FLOAT_EQ(q.dtdv, (1 - u) * 1 + u * 2);
  const TexCoordSample corner = s.uvs->at(1, 1, 1);
  EXPECT_EQ(corner.s, 2.0f);
  EXPECT_EQ(corner.t, 2.0f);
  EXPECT_EQ(s.uvs->at(2, 0.3f, 0.9f).s, 0.5f);
}

TEST_F(UvScene, BadUvsNameThePointer) {
  const std::string quad = R"({"type": "subdiv", "material": "c", "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]], "faces": [[0,1,2,3]])";
  EXPECT_THAT(errorOf(quad + R"(, "uvs": [[0,0],[1,0],[1,1]]})"),
              HasSubstr("/shapes/0/uvs: without 'uv_faces', one uv per vertex: 4 vertices, 3 uvs"));
  EXPECT_THAT(errorOf(quad + R"(, "uvs": [[0,0]], "uv_faces": [[0,0,0]]})"),
              HasSubstr("/shapes/0/uv_faces/0: expected 4 uv indices"));
  EXPECT_THAT(errorOf(quad + R"(, "uvs": [[0,0]], "uv_faces": [[0,0,1,0]]})"),
              HasSubstr("/shapes/0/uv_faces/0: uv index 1 out of range (0..0)"));
  EXPECT_THAT(errorOf(quad + R"(, "uvs": [[0,0]], "uv_faces": [[0,0,0,0], [0,0,0,0]]})"),
              HasSubstr("/shapes/0/uv_faces: expected one array of uv indices per face (1 faces)"));
  EXPECT_THAT(errorOf(quad + R"(, "uv_faces": [[0,0,0,0]]})"), HasSubstr("/shapes/0/uv_faces: 'uv_faces' needs 'uvs'"));
  EXPECT_THAT(errorOf(quad + R"(, "uvs": [[0,0],[1,0],[1,"NaN"],[0,1]]})"),
              HasSubstr("/shapes/0/uvs/2/1: expected a number, got string"));
  EXPECT_THAT(errorOf(quad + R"(, "uvs": [[0,0],[1,0],[1,1e39],[0,1]]})"), HasSubstr("/shapes/0/uvs/2/1: number out of range"));
  EXPECT_THAT(errorOf(quad + R"(, "uvs": [[0,0],[1,0],[1,1],[0]]})"), HasSubstr("/shapes/0/uvs/3: expected [s, t]"));
  EXPECT_THAT(errorOf(quad + R"(, "uvs": {"s": 0}})"), HasSubstr("/shapes/0/uvs: expected a non-empty array"));
  EXPECT_THAT(errorOf(quad + R"(, "uv_interpolation": "smooth"})"),
              HasSubstr("/shapes/0/uv_interpolation: unknown uv interpolation 'smooth' (expected none, corners-only"));
  EXPECT_THAT(errorOf(quad + R"(, "uv_interpolation": 3})"), HasSubstr("/shapes/0/uv_interpolation: expected a string"));
  EXPECT_THAT(errorOf(quad + R"(, "scheme": "polygon"})"), HasSubstr("(expected catmull-clark, loop or bilinear)"));
  temp_.write("q.obj", kTwoQuads);
  EXPECT_THAT(errorOf(R"({"type": "subdiv", "material": "c", "file": "q.obj", "uvs": [[0,0]]})"),
              HasSubstr("/shapes/0/uvs: 'uvs' belongs to the inline form"));
  temp_.write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/4\n");
  EXPECT_THAT(errorOf(R"({"type": "subdiv", "material": "c", "file": "bad.obj"})"),
              HasSubstr("bad.obj:line 5: texture coordinate index 4 out of range"));
  const std::string bl = R"({"type": "bilinear", "material": "c", "quads": [[[0,0,0],[1,0,0],[0,1,0],[1,1,0]]])";
  EXPECT_THAT(errorOf(bl + R"(, "uvs": []})"), HasSubstr("/shapes/0/uvs: expected one uv entry per patch: 1 patches, 0 entries"));
  EXPECT_THAT(errorOf(bl + R"(, "uvs": [[[0,0],[1,0],[0,1]]]})"), HasSubstr("/shapes/0/uvs/0: expected 4 corners"));
  EXPECT_THAT(errorOf(bl + R"(, "uvs": [[[0,0],[1,0],[0,1],[1,true]]]})"), HasSubstr("/shapes/0/uvs/0/3/1: expected a number"));
  EXPECT_THAT(errorOf(bl + R"(, "uvs": 1})"), HasSubstr("/shapes/0/uvs: expected an array"));
  EXPECT_THAT(errorOf(bl + "}", R"("st")"),
              HasSubstr("/materials/c/albedo/coordinates: unknown coordinates 'st' (expected patch or uv)"));
  EXPECT_THAT(errorOf(bl + "}", "1"), HasSubstr("/materials/c/albedo/coordinates: expected a string"));
}

}  // namespace
}  // namespace rayes
