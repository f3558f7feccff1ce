#include "geometry/subdiv_patch.h"

namespace rayes {

SubdivFacePatch::SubdivFacePatch(SubdivMeshPtr mesh, int leaf)
    : mesh_(std::move(mesh)),
      leaf_(leaf),
      bounds_(mesh_->leafBounds(leaf)),
      sizeBound_(mesh_->leafSizeBound(leaf)),
      errorCoefficient_(mesh_->leafErrorCoefficient(leaf)) {}

Box3 SubdivFacePatch::boundsOver(float u0, float u1, float v0, float v1) const {
  return mesh_->leafBoundsOver(leaf_, u0, u1, v0, v1);
}

SurfacePoint SubdivFacePatch::evaluate(float u, float v) const { return mesh_->evaluateLeaf(leaf_, u, v); }

void SubdivFacePatch::dice(int level, Vec3* positions, Vec3* normals) const {
  mesh_->diceLeaf(leaf_, level, positions, normals);
}

}  // namespace rayes
