// A Wavefront OBJ reader for subdivision control meshes (docs/scene-format.md, "subdiv").
//
// Reads `v x y z [w]`, `vt u [v [w]]` and `f` lines (triangles, quads, n-gons; `i`, `i/t`,
// `i//n`, `i/t/n`; one-based or negative relative indices), and OpenSubdiv's tag lines as its shape files write
// them, `t <name> <nint>/<nfloat>/<nstring> <ints> <floats> <strings>`, with zero-based
// indices:
//   t crease 2/1/0 v0 v1 s     crease the edges of each vertex pair (one sharpness, or one
//                              per pair)
//   t corner 1/1/0 v s         sharpen vertices (one sharpness, or one per vertex)
//   t hole 1/0/0 f             faces without a surface
//   t interpolateboundary 1/0/0 k   0 none, 1 edges only, 2 edges and corners (the default)
// Texture coordinates become the mesh's uv set (SubdivMeshDesc::uvs; their `t` indices its
// uvIndices): every face gives them, or none does (vt lines no face uses are dropped). Normals,
// groups, objects, smoothing groups and materials (vn vp g o s usemtl mtllib) are skipped, as
// are comments and blank lines. Anything else is an error.
//
// Errors (InputError(file, "line N", message), exit code 2): an unreadable file, a malformed
// or non-finite number, an unknown statement or tag, a face with fewer than 3 vertices, a
// vertex or texture coordinate index out of range, a face with texture coordinates for some
// corners only (or when other faces have none), an argument count that does not match a tag's
// header.
#pragma once
#include <string>
#include <vector>
#include "geometry/subdiv_mesh.h"

namespace rayes {

struct ObjMesh {
  SubdivMeshDesc mesh;  // scheme left at its default; the caller chooses it
  // The line each item came from, for messages about them (SubdivInputError's index).
  std::vector<int> vertexLine, faceLine, creaseLine, cornerLine, holeLine, uvLine;
};

// Parses OBJ text; `file` is used in messages only.
ObjMesh parseObj(const std::string& text, const std::string& file);
// Reads and parses a file.
ObjMesh loadObj(const std::string& path);

// The line of the item a SubdivInputError names (0 when it names the mesh as a whole).
int objLineOf(const ObjMesh& obj, const SubdivInputError& e);

}  // namespace rayes
