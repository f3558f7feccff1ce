// The leaves' uv sets read from a compiled scene's UvSets section (scene/leaf_uv_table.h,
// LeafUvTable::mapped): the same values as the table in memory, read record by record; a
// section whose size or records disagree with the leaves and tables they name is an InputError
// naming the file and the section or leaf, never a read outside the section.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <cstring>
#include <functional>
#include "core/error.h"
#include "geometry/compiled_file.h"
#include "scene/leaf_uv_table.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {

using ::testing::HasSubstr;
using compiled::SectionKind;
using compiled::UvRef;

// A .rayes holding only a UvSets section: `refs`, then `corners`.
std::string writeUvFile(const testing::TempFolder& t, const std::vector<UvRef>& refs, const std::vector<UvCorners>& corners,
                        const std::string& name = "uv.rayes") {
  const std::string path = t.path(name);
  CompiledFileWriter w(path, "test");
  w.beginSection(SectionKind::UvSets);
  w.write(refs.data(), refs.size() * sizeof(UvRef));
  w.write(corners.data(), corners.size() * sizeof(UvCorners));
  w.finish();
  return path;
}

std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.message();
  }
  return "(no InputError)";
}

const UvCorners kA = {{{0, 0}, {2, 0}, {0, 1}, {2.5f, 1.5f}}};
const UvCorners kB = {{{-1, 3}, {1, 3}, {-1, 5}, {1, 5}}};

TEST(MappedUvTable, ReadsTheSameValuesAsTheTableInMemory) {
  testing::TempFolder t;
  LeafUvTable memory;
  memory.setCorners(0, kA);
  memory.setCorners(2, kB);
  // Leaf 1 has none, leaf 3 lies beyond the last leaf with a uv set.
  const std::string path = writeUvFile(t, {memory.ref(0), memory.ref(1), memory.ref(2), memory.ref(3)}, {kA, kB});
  auto file = std::make_shared<const MappedFile>(path, 0);
  const auto mapped = LeafUvTable::mapped(file, 4, {});
  for (uint32_t leaf = 0; leaf < 5; ++leaf) {
    SCOPED_TRACE(leaf);
    ASSERT_EQ(mapped->has(leaf), memory.has(leaf));
    if (!memory.has(leaf)) continue;
    for (float u : {0.0f, 0.3f, 1.0f})
      for (float v : {0.0f, 0.7f, 1.0f}) {
        const TexCoordSample a = memory.at(leaf, u, v), b = mapped->at(leaf, u, v);
        EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0) << u << " " << v;
      }
  }
  EXPECT_EQ(mapped->bytes(), 0u) << "a mapped table holds no records in memory";
}

TEST(MappedUvTable, RecordsThatDisagreeWithTheSectionAreNamed) {
  testing::TempFolder t;
  // Two leaves' records and one corner set: the records name corners 1 (of 1) and the uv set of
  // topology 0, which the file does not have.
  const std::string path = writeUvFile(t, {{LeafUvTable::kCorners, 1}, {2, 0}}, {kA});
  auto file = std::make_shared<const MappedFile>(path, 0);
  const auto mapped = LeafUvTable::mapped(file, 2, {});
  EXPECT_THAT(messageOf([&] { mapped->has(0); }), HasSubstr(path + ":section uv_sets (leaf 0): uv corners 1 of 1"));
  EXPECT_THAT(messageOf([&] { mapped->has(1); }), HasSubstr(path + ":section uv_sets (leaf 1): the uv set of topology 0"));
  // A section of another leaf count: the records would not line up with the corners.
  EXPECT_THAT(messageOf([&] { LeafUvTable::mapped(file, 3, {}); }),
              HasSubstr(path + ":section uv_sets: not one 8-byte record per leaf (3 leaves)"));
  EXPECT_THAT(messageOf([&] { LeafUvTable::mapped(file, 7, {}); }), HasSubstr("not one 8-byte record per leaf"));
}

}  // namespace
}  // namespace rayes
