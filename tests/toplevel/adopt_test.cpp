// A stored tree adopted in place (a compiled scene's top level, TopLevelBvh::adopt): the same
// candidates in the same order as the tree that was built, every node and box read through
// the gate, and a stored tree the traversal could not walk safely refused at adoption.
#include <atomic>
#include <cstring>
#include <gtest/gtest.h>
#include <memory>
#include <stdexcept>

#include "core/gated_span.h"
#include "toplevel/toplevel_bvh.h"
#include "toplevel/toplevel_node.h"
#include "toplevel_test_util.h"

namespace rayes::testing {
namespace {

using toplevel::Node4;

// A gate over `bytes` bytes that admits every block it is asked for and counts the admissions;
// forgetAll() clears every ready byte (a release of everything), so reads go through admit()
// again.
struct ReadyBytes {
  std::unique_ptr<std::atomic<uint8_t>[]> ready;
  size_t blocks;
};
class CountingGate : private ReadyBytes, public BlockGate {
 public:
  explicit CountingGate(uint64_t bytes)
      : ReadyBytes{std::make_unique<std::atomic<uint8_t>[]>((bytes >> kBlockShift) + 1), (bytes >> kBlockShift) + 1},
        BlockGate(ready.get()) {}
  void forgetAll() {
    for (size_t b = 0; b < blocks; ++b) ready[b].store(0);
  }
  int admissions() const { return admissions_.load(); }
  bool admitted(uint64_t block) const { return everAdmitted_[block].load() != 0; }

 protected:
  void admit(uint64_t block) const override {
    EXPECT_LT(block, blocks) << "a read past the gated range";
    ++admissions_;
    everAdmitted_[block].store(1);
    ready[block].store(1);
  }

 private:
  mutable std::atomic<int> admissions_{0};
  std::unique_ptr<std::atomic<uint8_t>[]> everAdmitted_ = std::make_unique<std::atomic<uint8_t>[]>(blocks);
};

// A built tree's nodes copied behind a 128-byte header into block-aligned memory, as the
// compiled file stores them, and its boxes in a buffer of their own.
struct StoredCopy {
  static constexpr uint64_t kHeader = 128;
  std::unique_ptr<uint8_t[], void (*)(void*)> nodes{nullptr, std::free};
  std::vector<Box3> boxes;
  size_t nodeCount = 0;
  uint32_t root = 0;
  uint64_t nodeBytes() const { return kHeader + nodeCount * TopLevelBvh::kNodeBytes; }
  Node4& node(size_t k) { return reinterpret_cast<Node4*>(nodes.get() + kHeader)[k]; }

  explicit StoredCopy(const TopLevelBvh& built) {
    const TopLevelBvh::Stored s = built.stored();
    nodeCount = s.nodeCount;
    root = s.root;
    nodes.reset(static_cast<uint8_t*>(std::aligned_alloc(uint64_t(1) << BlockGate::kBlockShift,
                                                         ((nodeBytes() >> BlockGate::kBlockShift) + 1) << BlockGate::kBlockShift)));
    if (nodeCount > 0) std::memcpy(nodes.get() + kHeader, s.nodes, nodeCount * TopLevelBvh::kNodeBytes);  // no tree: null
    for (size_t i = 0; i < built.leafBoxes().size(); ++i) boxes.push_back(built.leafBoxes()[i]);
  }
  void adoptInto(TopLevelBvh& bvh, const BlockGate* nodeGate, const BlockGate* boxGate) {
    bvh.adopt(nodes.get() + kHeader, nodeCount, nodeGate, kHeader, root, GatedSpan<Box3>(boxes.data(), boxes.size(), boxGate));
  }
};

// Every candidate of every ray, a few at a time (resumption included).
std::vector<Candidate> allCandidates(const TopLevelBvh& bvh, const TestRay& r, int perCall) {
  std::vector<Candidate> got, buf(size_t(perCall) + 1);
  TraversalScratch scratch;
  float resumeEntry = -kInf;
  uint32_t resumeLeaf = 0;
  for (;;) {
    float next;
    const int k = bvh.collect(r.org, r.dir, r.tmin, r.tmax, resumeEntry, resumeLeaf, buf.data(), perCall, next, scratch);
    got.insert(got.end(), buf.begin(), buf.begin() + k);
    if (k == 0) break;
    resumeEntry = buf[size_t(k) - 1].entry;
    resumeLeaf = buf[size_t(k) - 1].leaf;
  }
  return got;
}

TEST(Adopt, StoredTreeGivesTheBuiltTreesCandidatesThroughItsGates) {
  // Enough leaves for the nodes to fill several 64 KiB blocks (512 nodes each).
  const std::vector<Box3> boxes = randomBoxes(6000, 41);
  const std::vector<TestRay> rays = randomRays(300, 42, boxes);
  TopLevelBvh built;
  built.build(boxes);
  StoredCopy copy(built);
  ASSERT_GT(copy.nodeBytes() >> BlockGate::kBlockShift, 2u) << "the nodes must span several blocks";
  for (bool forget : {false, true}) {
    SCOPED_TRACE(forget ? "released before every ray" : "kept");
    CountingGate nodeGate(copy.nodeBytes()), boxGate(boxes.size() * sizeof(Box3));
    TopLevelBvh adopted;
    copy.adoptInto(adopted, &nodeGate, &boxGate);
    EXPECT_TRUE(adopted.adopted());
    EXPECT_EQ(adopted.bytes(), 0u) << "an adopted tree holds none of its nodes";
    EXPECT_EQ(adopted.nodeCount(), built.nodeCount());
    EXPECT_EQ(adopted.leafCount(), built.leafCount());
    EXPECT_EQ(adopted.bounds().lo, built.bounds().lo);
    EXPECT_EQ(adopted.bounds().hi, built.bounds().hi);
    // Adoption checks every node: every block of nodes is admitted once at least.
    for (uint64_t b = 0; b <= (copy.nodeBytes() - 1) >> BlockGate::kBlockShift; ++b) EXPECT_TRUE(nodeGate.admitted(b)) << b;
    const int afterAdoption = nodeGate.admissions();
    int raysWithCandidates = 0;  // each reads the root at least: an admission after forgetAll()
    for (const TestRay& r : rays) {
      raysWithCandidates += !bruteForce(boxes, r).empty();
      if (forget) nodeGate.forgetAll(), boxGate.forgetAll();
      for (int n : {1, 5}) ASSERT_EQ(allCandidates(adopted, r, n), allCandidates(built, r, n));
      ASSERT_EQ(allCandidates(adopted, r, 1), bruteForce(boxes, r));
    }
    TraversalScratch scratch;
    for (size_t i = 0; i < 200; ++i) {
      const Box3& q = boxes[i * 7];
      std::vector<uint32_t> a, b;
      adopted.overlapping(q, a, scratch);
      built.overlapping(q, b, scratch);
      EXPECT_EQ(a, b);
      EXPECT_EQ(adopted.anyOtherLeafMeets(q, uint32_t(i * 7)), built.anyOtherLeafMeets(q, uint32_t(i * 7)));
    }
    for (size_t i = 0; i < boxes.size(); i += 97) EXPECT_EQ(std::memcmp(&adopted.leafBoxes().at(i), &boxes[i], sizeof(Box3)), 0);
    EXPECT_TRUE(adopted.leafBoxes().gated());
    if (forget) EXPECT_GE(nodeGate.admissions() - afterAdoption, raysWithCandidates) << "released blocks are admitted again";
    else EXPECT_EQ(nodeGate.admissions(), afterAdoption) << "adoption admitted every block already";
  }
}

TEST(Adopt, OneLeafAndNoLeaf) {
  for (const std::vector<Box3>& boxes : {std::vector<Box3>{{{1, 2, 3}, {4, 5, 6}}}, std::vector<Box3>{}}) {
    TopLevelBvh built;
    built.build(boxes);
    StoredCopy copy(built);
    TopLevelBvh adopted;
    copy.adoptInto(adopted, nullptr, nullptr);
    const TestRay r{{0, 0, 0}, normalize(Vec3{1, 1.2f, 1.4f})};
    EXPECT_EQ(allCandidates(adopted, r, 2), allCandidates(built, r, 2));
    EXPECT_EQ(allCandidates(adopted, r, 2).size(), boxes.size());
  }
}

// Whatever a stored tree holds (its blocks' CRCs only say it is what was written), adoption
// leaves no way out of bounds or into a loop.
TEST(Adopt, RefusesTreesTheTraversalCannotWalk) {
  const std::vector<Box3> boxes = randomBoxes(300, 43);
  TopLevelBvh built;
  built.build(boxes);
  struct Case {
    const char* name;
    void (*spoil)(StoredCopy&);
  };
  const Case cases[] = {
      {"a child before its parent (a loop)", [](StoredCopy& c) { c.node(1).child[0] = 0; }},
      {"a child beyond the nodes", [](StoredCopy& c) { c.node(0).child[0] = uint32_t(c.nodeCount); }},
      {"a leaf beyond the boxes", [](StoredCopy& c) { c.node(c.nodeCount - 1).child[0] = toplevel::leafRef(300); }},
      {"no children", [](StoredCopy& c) { c.node(2).count = 0; }},
      {"five children", [](StoredCopy& c) { c.node(2).count = 5; }},
      {"an unused slot a ray can enter", [](StoredCopy& c) {
         for (size_t k = 0; k < c.nodeCount; ++k)
           if (c.node(k).count < 4) { c.node(k).lo[0][3] = 0; return; }
       }},
      {"an unused slot naming a leaf", [](StoredCopy& c) {
         for (size_t k = 0; k < c.nodeCount; ++k)
           if (c.node(k).count < 4) { c.node(k).child[3] = toplevel::leafRef(0); return; }
       }},
      {"a root other than node 0", [](StoredCopy& c) { c.root = 1; }},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(k.name);
    StoredCopy copy(built);
    k.spoil(copy);
    TopLevelBvh adopted;
    EXPECT_THROW(copy.adoptInto(adopted, nullptr, nullptr), std::invalid_argument);
  }
  StoredCopy good(built);
  TopLevelBvh adopted;
  EXPECT_NO_THROW(good.adoptInto(adopted, nullptr, nullptr));
}

}  // namespace
}  // namespace rayes::testing
