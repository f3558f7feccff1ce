// The built tree itself: containment of leaf boxes, counts, empty slots, 4-wide nodes.
#include <cstring>
#include <gtest/gtest.h>

#include "toplevel/toplevel_bvh.h"
#include "toplevel/toplevel_node.h"
#include "toplevel_test_util.h"

namespace rayes::testing {
namespace {

using toplevel::Inspector;
using toplevel::Node4;

struct TreeStats {
  size_t innerNodes = 0;
  size_t fourWide = 0;
  std::vector<int> leafSeen;  // per leaf id
};

Box3 childBox(const Node4& n, int i) {
  return {{n.lo[0][i], n.lo[1][i], n.lo[2][i]}, {n.hi[0][i], n.hi[1][i], n.hi[2][i]}};
}

// Walks the subtree of `ref`, checking every node; returns the union of the leaf boxes below.
Box3 walk(std::span<const Node4> nodes, uint32_t ref, const std::vector<Box3>& boxes,
          TreeStats& stats) {
  if (toplevel::isLeafRef(ref)) {
    const uint32_t id = toplevel::refLeafId(ref);
    EXPECT_LT(id, boxes.size());
    if (id >= boxes.size()) return {};
    ++stats.leafSeen[id];
    return boxes[id];
  }
  EXPECT_LT(ref, nodes.size());
  if (ref >= nodes.size()) return {};
  const Node4& n = nodes[ref];
  ++stats.innerNodes;
  stats.fourWide += n.count == 4;
  EXPECT_GE(n.count, 2u);
  EXPECT_LE(n.count, 4u);
  Box3 all;
  for (int i = 0; i < 4; ++i) {
    const Box3 stored = childBox(n, i);
    if (i >= int(n.count)) {  // an unused slot: inverted, so no ray can enter it
      EXPECT_EQ(n.child[i], toplevel::kEmptyRef);
      EXPECT_EQ(stored.lo, (Vec3{kInf, kInf, kInf}));
      EXPECT_EQ(stored.hi, (Vec3{-kInf, -kInf, -kInf}));
      continue;
    }
    const Box3 below = walk(nodes, n.child[i], boxes, stats);
    EXPECT_TRUE(stored.contains(below)) << "node " << ref << " child " << i;
    EXPECT_FALSE(stored.empty());
    all.extend(below);
  }
  return all;
}

TreeStats checkTree(const TopLevelBvh& bvh, const std::vector<Box3>& boxes) {
  TreeStats stats;
  stats.leafSeen.assign(boxes.size(), 0);
  const uint32_t root = Inspector::root(bvh);
  const auto nodes = Inspector::nodes(bvh);
  Box3 sceneBox;
  for (const Box3& b : boxes) sceneBox.extend(b);  // empty boxes change nothing
  if (root != toplevel::kNoRoot) {
    const Box3 all = walk(nodes, root, boxes, stats);
    EXPECT_EQ(all.lo, bvh.bounds().lo);
    EXPECT_EQ(all.hi, bvh.bounds().hi);
  }
  EXPECT_EQ(sceneBox.lo, bvh.bounds().lo);
  EXPECT_EQ(sceneBox.hi, bvh.bounds().hi);
  for (size_t i = 0; i < boxes.size(); ++i)
    EXPECT_EQ(stats.leafSeen[i], boxes[i].empty() ? 0 : 1) << "leaf " << i;
  EXPECT_EQ(stats.innerNodes, bvh.nodeCount());  // every node reachable, none twice
  EXPECT_EQ(bvh.bytes(), bvh.nodeCount() * sizeof(Node4) + boxes.size() * sizeof(Box3));
  EXPECT_EQ(bvh.leafBoxes().size(), boxes.size());
  for (size_t i = 0; i < boxes.size() && i < bvh.leafBoxes().size(); ++i)
    EXPECT_EQ(std::memcmp(&bvh.leafBoxes().at(i), &boxes[i], sizeof(Box3)), 0) << "leaf " << i;
  EXPECT_EQ(bvh.leafCount(), boxes.size());
  return stats;
}

TEST(Tree, LargeRandomSceneIsAConsistentFourWideTree) {
  const std::vector<Box3> boxes = randomBoxes(20000, 71);
  TopLevelBvh bvh;
  bvh.build(boxes);
  const TreeStats stats = checkTree(bvh, boxes);
  // Embree fills the upper levels to 4 children; near the leaves SAH leaves many 2 and 3.
  EXPECT_EQ(Inspector::nodes(bvh)[Inspector::root(bvh)].count, 4u);
  EXPECT_GT(stats.fourWide, stats.innerNodes / 4);
  size_t nonEmpty = 0;
  for (const Box3& b : boxes) nonEmpty += !b.empty();
  EXPECT_LT(nonEmpty, boxes.size());  // the scene has empty boxes to skip
  // A tree of n leaves with 2..4 children per node has between (n-1)/3 and n-1 inner nodes.
  EXPECT_GE(bvh.nodeCount(), (nonEmpty - 1) / 3);
  EXPECT_LE(bvh.nodeCount(), nonEmpty - 1);
}

TEST(Tree, SmallAndDegenerateInputs) {
  for (int n : {2, 3, 4, 5, 17}) {
    SCOPED_TRACE(n);
    const std::vector<Box3> boxes = randomBoxes(n, 80 + n);
    TopLevelBvh bvh;
    bvh.build(boxes);
    checkTree(bvh, boxes);
  }
  // All identical, all flat, one point-sized.
  const std::vector<Box3> same(500, Box3{{1, 2, 3}, {4, 5, 6}});
  const std::vector<Box3> flat(300, Box3{{0, 0, 7}, {1, 1, 7}});
  const std::vector<Box3> point(2, Box3{{1, 1, 1}, {1, 1, 1}});
  for (const auto* boxes : {&same, &flat, &point}) {
    TopLevelBvh bvh;
    bvh.build(*boxes);
    checkTree(bvh, *boxes);
  }
}

TEST(Tree, NodeSlabTestMatchesIntersectBox) {
  // The 4-wide test must agree bit for bit with intersectBox, inverted slots always missing.
  const std::vector<Box3> boxes = randomBoxes(400, 91);
  const std::vector<TestRay> rays = randomRays(400, 92, boxes);
  Node4 node;
  int hits = 0;
  for (size_t base = 0; base + 4 <= boxes.size(); base += 4) {
    for (int i = 0; i < 4; ++i) {
      const Box3 b = (i == 3 && base % 8 == 0) ? Box3{} : boxes[base + i];
      for (int a = 0; a < 3; ++a) { node.lo[a][i] = b.lo[a]; node.hi[a][i] = b.hi[a]; }
    }
    for (const TestRay& r : rays) {
      const RayBoxQuery q(r.org, r.dir);
      float entry[4], exit[4];
      const unsigned mask = toplevel::intersectChildren(node, RayBox4Query(q), r.tmin, r.tmax, entry, exit);
      for (int i = 0; i < 4; ++i) {
        float e, x;
        const bool hit = intersectBox(q, childBox(node, i).lo, childBox(node, i).hi, r.tmin, r.tmax, e, x);
        ASSERT_EQ(((mask >> i) & 1) != 0, hit);
        if (i == 3 && base % 8 == 0) {
          ASSERT_FALSE(hit);
        }
        if (!hit) continue;
        ++hits;
        ASSERT_EQ(entry[i], e);
        ASSERT_EQ(exit[i], x);
      }
    }
  }
  EXPECT_GT(hits, 1000);
}

}  // namespace
}  // namespace rayes::testing
