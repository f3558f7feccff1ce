// A patch record (geometry/patch_record.h) rebuilds the patch it was made from, bit for bit:
// the same bounds, facts, evaluations and dicings, for every kind a compiled scene holds; a
// damaged record is refused with a reason, never decoded into something else.
#include <cstring>
#include <gtest/gtest.h>
#include "geometry/disk_patch.h"
#include "geometry/forest.h"
#include "geometry/leaf_source.h"
#include "geometry/moving_patch.h"
#include "geometry/patch_record.h"
#include "geometry/subdiv_patch.h"
#include "geometry/subdiv_uv.h"
#include "support/displaced_test_shapes.h"
#include "support/subdiv_test_meshes.h"

namespace rayes {
namespace {

std::vector<uint8_t> recordOf(const Patch& p) {
  std::vector<uint8_t> out;
  EXPECT_EQ(encodePatch(p, out), "");
  return out;
}

// Everything a render asks of a patch, compared bit for bit.
void expectSamePatch(const Patch& a, const Patch& b) {
  EXPECT_STREQ(a.kind(), b.kind());
  EXPECT_TRUE(test::sameBits(a.bounds().lo, b.bounds().lo) && test::sameBits(a.bounds().hi, b.bounds().hi));
  const LeafFacts fa = LeafFacts::of(a), fb = LeafFacts::of(b);
  EXPECT_TRUE(test::sameBits(fa.sizeBound, fb.sizeBound));
  EXPECT_TRUE(test::sameBits(fa.dicingError, fb.dicingError));
  EXPECT_EQ(fa.timeSamples, fb.timeSamples);
  EXPECT_EQ(fa.displaced, fb.displaced);
  EXPECT_EQ(fa.borderClosure, fb.borderClosure);
  for (int s = 0; s < a.timeSamples(); ++s) {
    EXPECT_TRUE(test::sameBits(a.sampleTime(s), b.sampleTime(s)));
    const int level = 3, n = (1 << level) + 1;
    std::vector<Vec3> pa(n * n), na(n * n), pb(n * n), nb(n * n);
    a.diceAt(s, level, pa.data(), na.data());
    b.diceAt(s, level, pb.data(), nb.data());
    EXPECT_EQ(std::memcmp(pa.data(), pb.data(), pa.size() * sizeof(Vec3)), 0) << "positions, sample " << s;
    EXPECT_EQ(std::memcmp(na.data(), nb.data(), na.size() * sizeof(Vec3)), 0) << "normals, sample " << s;
    const Box3 ba = a.boundsOverAt(s, 0.25f, 0.5f, 0.0f, 0.75f), bb = b.boundsOverAt(s, 0.25f, 0.5f, 0.0f, 0.75f);
    EXPECT_TRUE(test::sameBits(ba.lo, bb.lo) && test::sameBits(ba.hi, bb.hi));
  }
}

std::vector<PatchPtr> everyKind() {
  std::vector<PatchPtr> kinds;
  NoiseParams np;
  np.amplitude = 0.1f;
  np.frequency = 3;
  np.seed = 7;
  np.ridged = true;
  const auto noise = std::make_shared<NoiseDisplacement>(np);
  for (const test::Shape& s : test::testShapes()) {
    kinds.push_back(s.patch);
    kinds.push_back(std::make_shared<DisplacedPatch>(s.patch, noise));
    // With a reference surface of its own (a transformed shape's object-space patch).
    kinds.push_back(std::make_shared<DisplacedPatch>(s.patch, noise, test::testShapes()[2].patch));
  }
  const auto base = test::testShapes()[0].patch;
  const auto moved = std::make_shared<BezierPatch>(test::transformed(test::loadTeapot()[0], 1.5f, Vec3{0.5f, 0, 0}));
  kinds.push_back(std::make_shared<MovingPatch>(std::vector<PatchPtr>{base, moved}, std::vector<float>{0.0f, 1.0f}));
  kinds.push_back(std::make_shared<MovingPatch>(
      std::vector<PatchPtr>{std::make_shared<DisplacedPatch>(base, noise), std::make_shared<DisplacedPatch>(moved, noise, base)},
      std::vector<float>{-0.5f, 2.0f}));
  return kinds;
}

TEST(PatchRecord, RebuildsEveryKindBitForBit) {
  for (const PatchPtr& p : everyKind()) {
    SCOPED_TRACE(p->kind());
    const std::vector<uint8_t> r = recordOf(*p);
    expectSamePatch(*p, *decodePatch(r.data(), r.size()));
  }
}

TEST(PatchRecord, NamesWhatItCannotEncode) {
  std::vector<uint8_t> out;
  EXPECT_NE(encodePatch(DiskPatch({0, 0, 0}, {0, 0, 1}, 1), out).find("'disk'"), std::string::npos);
  const auto map = test::randomMap(8, 8, 1);
  const DisplacedPatch heightMapped(test::testShapes()[2].patch, std::make_shared<HeightMapDisplacement>(map, 0.1f, 0.0f));
  out.clear();
  EXPECT_NE(encodePatch(heightMapped, out).find("height-map displacement without a table"), std::string::npos);
  // With a table, a map must name its file: one made in memory cannot be opened again.
  RecordTableIndex index;
  index.add(heightMapped);
  out.clear();
  EXPECT_NE(encodePatch(heightMapped, out, &index).find("made in memory"), std::string::npos);
}

// A cube with every tag a topology carries (crease, corner, hole, a uv set with a seam, a
// boundary rule, a uv interpolation), moved to two time samples and displaced by a height map
// that names a file.
struct SharedKinds {
  std::shared_ptr<const SubdivTopology> topology;
  SubdivMeshPtr at0, at1;
  std::shared_ptr<const HeightMapDisplacement> map;
  PatchPtr moving, displaced;

  SharedKinds() {
    SubdivMeshDesc d = test::cube();
    d.creases = {{0, 2, 2.5f}};
    d.corners = {{7, 4.0f}};
    d.holes = {5};
    d.boundary = SubdivBoundary::EdgeOnly;
    d.uvInterpolation = SubdivUvInterpolation::CornersPlus1;
    d.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5f, 0.5f}};
    for (int f = 0; f < 6; ++f)
      for (int k = 0; k < 4; ++k) d.uvIndices.push_back(f == 2 && k == 0 ? 4 : k);
    topology = buildSubdivTopology(d);
    std::vector<Vec3> moved = d.positions;
    for (Vec3& p : moved) p = p + Vec3{0.25f, 0, 0};
    at0 = SubdivMesh::build(topology, d.positions);
    at1 = SubdivMesh::build(topology, moved);
    map = std::make_shared<HeightMapDisplacement>(test::randomMap(8, 8, 1), 0.1f, 0.02f, HeightMapOrigin{"h.exr", "Y"});
    moving = std::make_shared<MovingPatch>(std::vector<PatchPtr>{at0->patches()[1], at1->patches()[1]},
                                           std::vector<float>{0.0f, 1.0f});
    displaced = std::make_shared<DisplacedPatch>(at0->patches()[2], map, at1->patches()[2]);
  }
};

// Subdivision faces and height maps: the records name the shared objects by index, the objects
// are rebuilt from their own records (the topology) or passed in (meshes, maps), and the patch
// comes back bit for bit.
TEST(PatchRecord, SharedObjectsAreNamedByIndexAndRebuildTheSamePatch) {
  const SharedKinds k;
  RecordTableIndex index;
  index.add(*k.moving);
  index.add(*k.displaced);
  ASSERT_EQ(index.meshes().size(), 2u);
  ASSERT_EQ(index.topologies().size(), 1u) << "a moving mesh's time samples share one topology";
  ASSERT_EQ(index.heightMaps().size(), 1u);
  std::vector<uint8_t> topo;
  encodeSubdivTopology(*k.topology, topo);
  const auto rebuilt = decodeSubdivTopology(topo.data(), topo.size());
  RecordTables tables;
  for (const SubdivMesh* m : index.meshes()) tables.meshes.push_back(SubdivMesh::build(rebuilt, m->controlPoints()));
  tables.heightMaps.push_back(k.map);
  for (const PatchPtr& p : {k.moving, k.displaced}) {
    SCOPED_TRACE(p->kind());
    std::vector<uint8_t> r;
    ASSERT_EQ(encodePatch(*p, r, &index), "");
    expectSamePatch(*p, *decodePatch(r.data(), r.size(), &tables));
  }
  // The uv set of the rebuilt topology is the same function.
  const SubdivUvSet a(k.topology), b(rebuilt);
  ASSERT_EQ(a.leafCount(), b.leafCount());
  for (int leaf = 0; leaf < a.leafCount(); ++leaf) {
    float sa[2], ua[2], va[2], sb[2], ub[2], vb[2];
    a.evaluate(leaf, 0.3f, 0.7f, sa, ua, va);
    b.evaluate(leaf, 0.3f, 0.7f, sb, ub, vb);
    EXPECT_EQ(std::memcmp(sa, sb, sizeof sa) | std::memcmp(ua, ub, sizeof ua) | std::memcmp(va, vb, sizeof va), 0) << leaf;
  }
  // Without the tables, or with an index beyond them, the record is refused.
  std::vector<uint8_t> r;
  ASSERT_EQ(encodePatch(*k.moving, r, &index), "");
  EXPECT_THROW(decodePatch(r.data(), r.size()), std::invalid_argument);
  RecordTables short_;
  short_.meshes.push_back(tables.meshes[0]);
  EXPECT_THROW(decodePatch(r.data(), r.size(), &short_), std::invalid_argument);
}

// A forest's leaf: 13 bytes naming its forest and its piece; decoded by the forest's
// ForestPatches, here over a copy of the forest's tables (as a compiled scene's mapping holds
// them), it is the patch the forest makes, bit for bit, for every part, placed or not.
TEST(PatchRecord, AForestLeafIsMadeFromItsForestsTablesBitForBit) {
  ForestParams fp;
  fp.trees = 2;
  fp.detail = 1;
  fp.terrainTiles = 3;
  fp.leavesPerTwig = 2;
  for (const Transform& placement : {Transform{}, Transform::translate(1, 2, 3) * Transform::rotate(Vec3{0, 1, 0}, 35) * Transform::scale(2.5f, 2.5f, 2.5f)}) {
    fp.placement = placement;
    const Forest forest(fp);
    const std::vector<ForestBranch> branches(&forest.branch(0), &forest.branch(0) + forest.branchCount());
    const std::vector<ForestFoliage> foliage(&forest.foliage(0), &forest.foliage(0) + forest.foliageCount());
    RecordTableIndex index;
    EXPECT_EQ(index.addForest(forest), 0u);
    EXPECT_EQ(index.addForest(forest), 0u) << "one forest, one index";
    RecordTables tables;
    tables.forests.push_back(std::make_shared<const ForestPatches>(
        forest.params(), GatedSpan<ForestBranch>(branches.data(), branches.size()),
        GatedSpan<ForestFoliage>(foliage.data(), foliage.size())));
    for (size_t i = 0; i < forest.size(); ++i) {
      SCOPED_TRACE(i);
      std::vector<uint8_t> r;
      encodeForestLeaf(index.forestIndex(&forest), forest.leaf(i), r);
      ASSERT_EQ(r.size(), 13u);
      expectSamePatch(*forest.makePatch(i), *decodePatch(r.data(), r.size(), &tables));
      for (size_t n = 0; n < r.size(); ++n) EXPECT_THROW(decodePatch(r.data(), n, &tables), std::invalid_argument) << n;
    }
  }
}

// A forest leaf outside its forest's tables, or naming a forest that is not there, is refused.
TEST(PatchRecord, AForestLeafOutsideItsTablesIsRefused) {
  ForestParams fp;
  fp.trees = 1;
  fp.detail = 0;
  fp.terrainTiles = 2;
  const Forest forest(fp);
  RecordTables tables;
  tables.forests.push_back(std::make_shared<const ForestPatches>(
      forest.params(), GatedSpan<ForestBranch>(&forest.branch(0), forest.branchCount()), GatedSpan<ForestFoliage>()));
  const auto decodes = [&](ForestLeaf leaf, uint32_t f = 0) {
    std::vector<uint8_t> r;
    encodeForestLeaf(f, leaf, r);
    try {
      decodePatch(r.data(), r.size(), &tables);
      return std::string();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
  };
  using Part = ForestLeaf::Part;
  EXPECT_EQ(decodes({Part::Terrain, 0, 0, 3}), "");
  EXPECT_EQ(decodes({Part::Terrain, 0, 0, 4}), "terrain tile 4 of 4");
  EXPECT_EQ(decodes({Part::Bark, 3, 2, 0}), "");
  EXPECT_EQ(decodes({Part::Bark, 0, 0, 1}), "branch 1 of 1");
  EXPECT_EQ(decodes({Part::Bark, 4, 0, 0}), "quarter 4 of 4");
  EXPECT_EQ(decodes({Part::Bark, 0, 3, 0}), "segment 3 of a branch of 3");
  EXPECT_EQ(decodes({Part::Foliage, 0, 0, 0}), "foliage leaf 0 of 0");
  EXPECT_EQ(decodes({Part(3), 0, 0, 0}), "forest part 3");
  EXPECT_EQ(decodes({Part::Terrain, 0, 0, 0}, 1), "forest 1 of 1");
  std::vector<uint8_t> r;
  encodeForestLeaf(0, {Part::Terrain, 0, 0, 0}, r);
  EXPECT_THROW(decodePatch(r.data(), r.size()), std::invalid_argument) << "no tables";
}

TEST(PatchRecord, ATopologyRecordRefusesEveryTruncationAndExtension) {
  const SharedKinds k;
  std::vector<uint8_t> topo;
  encodeSubdivTopology(*k.topology, topo);
  for (size_t n = 0; n < topo.size(); ++n) EXPECT_THROW(decodeSubdivTopology(topo.data(), n), std::invalid_argument) << n;
  topo.push_back(0);
  EXPECT_THROW(decodeSubdivTopology(topo.data(), topo.size()), std::invalid_argument);
  topo.pop_back();
  // The uv count (5 uvs, 24 uv indices after them) with its top bit set: doubled, it would wrap
  // to exactly the floats that follow, so only a check of the count itself refuses it.
  const size_t uvCountAt = topo.size() - 4 - 24 * 4 - 5 * 8 - 4;
  uint32_t count;
  std::memcpy(&count, topo.data() + uvCountAt, 4);
  ASSERT_EQ(count, 5u);
  count |= 0x80000000u;
  std::memcpy(topo.data() + uvCountAt, &count, 4);
  EXPECT_THROW(decodeSubdivTopology(topo.data(), topo.size()), std::invalid_argument);
}

TEST(PatchRecord, RefusesEveryTruncationAndExtension) {
  for (const PatchPtr& p : everyKind()) {
    const std::vector<uint8_t> r = recordOf(*p);
    for (size_t n = 0; n < r.size(); ++n) EXPECT_THROW(decodePatch(r.data(), n), std::invalid_argument) << n;
    std::vector<uint8_t> longer = r;
    longer.push_back(0);
    EXPECT_THROW(decodePatch(longer.data(), longer.size()), std::invalid_argument);
  }
}

TEST(PatchRecord, RefusesUnknownTagsAndImpossibleValues) {
  const uint8_t unknown[] = {99};
  EXPECT_THROW(decodePatch(unknown, 1), std::invalid_argument);
  // A moving record whose count is absurd is refused before anything is reserved.
  std::vector<uint8_t> moving = recordOf(*everyKind()[9]);
  ASSERT_EQ(moving[0], 4);
  const uint32_t huge = 0xffffffffu;
  std::memcpy(moving.data() + 1, &huge, 4);
  EXPECT_THROW(decodePatch(moving.data(), moving.size()), std::invalid_argument);
  // Noise octaves out of range: NoiseDisplacement's own refusal.
  std::vector<uint8_t> displaced = recordOf(*everyKind()[1]);
  ASSERT_EQ(displaced[0], 3);
  const int32_t octaves = 99;
  std::memcpy(displaced.data() + 1 + 1 + 1 + 8, &octaves, 4);  // tag, hasReference, noise tag, amplitude, frequency
  EXPECT_THROW(decodePatch(displaced.data(), displaced.size()), std::invalid_argument);
}

}  // namespace
}  // namespace rayes
