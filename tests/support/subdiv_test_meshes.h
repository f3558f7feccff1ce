// Small control meshes with known limit surfaces, shared by the subdivision tests and
// bench/dicing_subdiv.cpp (which must dice exactly the faces the tests check).
#pragma once
#include <cmath>
#include "geometry/subdiv_mesh.h"

namespace rayes::test {

// The cube [-h, h]^3: six regular-boundary-free quads, eight valence-3 vertices.
inline SubdivMeshDesc cube(float h = 1.0f) {
  SubdivMeshDesc d;
  for (int k = 0; k < 8; ++k) d.positions.push_back({k & 1 ? h : -h, k & 2 ? h : -h, k & 4 ? h : -h});
  d.faceSizes = {4, 4, 4, 4, 4, 4};
  d.faceVertices = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
  return d;
}

// A pentagonal prism: two pentagons (QUAD_SUBFACES) and five quads.
inline SubdivMeshDesc pentagonalPrism() {
  SubdivMeshDesc d;
  for (int z = 0; z < 2; ++z)
    for (int k = 0; k < 5; ++k) {
      const float a = 6.2831853f * float(k) / 5.0f;
      d.positions.push_back({std::cos(a), std::sin(a), z ? 1.0f : -1.0f});
    }
  d.faceSizes = {5, 5, 4, 4, 4, 4, 4};
  d.faceVertices = {4, 3, 2, 1, 0, 5, 6, 7, 8, 9};
  for (int k = 0; k < 5; ++k) {
    const int n = (k + 1) % 5;
    for (int v : {k, n, n + 5, k + 5}) d.faceVertices.push_back(v);
  }
  return d;
}

// An octahedron as an all-triangle Loop mesh: every vertex has valence 4 (irregular for Loop).
inline SubdivMeshDesc octahedron() {
  SubdivMeshDesc d;
  d.scheme = SubdivScheme::Loop;
  d.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const int f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (const auto& t : f) {
    d.faceSizes.push_back(3);
    for (int v : t) d.faceVertices.push_back(v);
  }
  return d;
}

}  // namespace rayes::test
