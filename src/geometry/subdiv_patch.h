// One leaf of a subdivision surface: a quad face, or one quad sub-face of a non-quad face,
// over the unit square. Holds its mesh (shared, immutable) and its leaf index; everything is
// delegated to SubdivMesh (subdiv_mesh.h), which keeps the seams between leaves watertight.
#pragma once
#include "geometry/subdiv_mesh.h"

namespace rayes {

class SubdivFacePatch final : public Patch {
 public:
  SubdivFacePatch(SubdivMeshPtr mesh, int leaf);

  // Regular faces: the box of the face's bicubic Bézier control points. Irregular faces: the
  // box of Bfr's control points and patch points (the limit surface is a convex combination
  // of the control points). Padded for float rounding.
  Box3 bounds() const override { return bounds_; }
  // Regular faces: the Bézier sub-patch hull (as BezierPatch). Irregular: sampled limit points
  // plus a bilinear-interpolation margin from sampled second derivatives (x2), intersected
  // with bounds() (see SubdivMesh::leafBoundsOver; sampled, not proven).
  Box3 boundsOver(float u0, float u1, float v0, float v1) const override;
  // Regular faces: the Bézier control polylines (a true bound). Irregular: 1.25 x the longest
  // iso-polyline through a 5 x 5 grid of limit points (an estimate, which is all LOD needs).
  float sizeBound() const override { return sizeBound_; }
  // Regular faces: from second differences of the Bézier points (as BezierPatch). Irregular:
  // the default (the box's longest side).
  float dicingErrorCoefficient() const override { return errorCoefficient_; }
  SurfacePoint evaluate(float u, float v) const override;
  void dice(int level, Vec3* positions, Vec3* normals) const override;
  const char* kind() const override { return "subdiv"; }
  bool isSubdivision() const override { return true; }

  const SubdivMesh& mesh() const { return *mesh_; }
  int leaf() const { return leaf_; }

 private:
  SubdivMeshPtr mesh_;
  int leaf_;
  Box3 bounds_;
  float sizeBound_, errorCoefficient_;
};

}  // namespace rayes
