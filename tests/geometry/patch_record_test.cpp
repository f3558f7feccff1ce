// A patch record (geometry/patch_record.h) rebuilds the patch it was made from, bit for bit:
// the same bounds, facts, evaluations and dicings, for every kind a compiled scene holds; a
// damaged record is refused with a reason, never decoded into something else.
#include <cstring>
#include <gtest/gtest.h>
#include "geometry/disk_patch.h"
#include "geometry/leaf_source.h"
#include "geometry/moving_patch.h"
#include "geometry/patch_record.h"
#include "support/displaced_test_shapes.h"

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
  EXPECT_NE(encodePatch(heightMapped, out).find("'image'"), std::string::npos);
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
