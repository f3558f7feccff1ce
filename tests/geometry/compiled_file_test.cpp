// The .rayes container (geometry/compiled_file.h): what is written is read back; a file that
// is not one, of another version, truncated or corrupt anywhere is refused naming the file and
// the place (the header at opening, a block at its first read); a resident budget keeps the
// mapping's blocks within it, measured by the kernel, without changing a byte read.
#include <cstring>
#include <fstream>
#include <numeric>
#include <gtest/gtest.h>
#include "core/error.h"
#include "geometry/compiled_file.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {

using compiled::SectionKind;

constexpr uint64_t kWords = 4 * compiled::kBlockBytes / 4 + 1000;  // a records section of 5 blocks

// A file with a small scene section and a records section of kWords counting words.
std::string writeSample(const testing::TempFolder& t, const std::string& name = "s.rayes") {
  const std::string path = t.path(name);
  CompiledFileWriter w(path, "test");
  w.beginSection(SectionKind::Scene);
  w.write("{}", 2);
  w.beginSection(SectionKind::Records);
  std::vector<uint32_t> words(kWords);
  std::iota(words.begin(), words.end(), 0u);
  w.write(words.data(), words.size() * 4);
  w.finish();
  return path;
}

void patch(const std::string& path, uint64_t at, char byte) {
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(std::streamoff(at));
  f.put(byte);
}

std::string openError(const std::string& path) {
  try {
    MappedFile f(path, 0);
  } catch (const InputError& e) {
    return e.message();
  }
  return "";
}

TEST(CompiledFile, ReadsBackWhatWasWrittenSectionsOnBlocks) {
  testing::TempFolder t;
  MappedFile f(writeSample(t), 0);
  EXPECT_EQ(f.sectionBytes(SectionKind::Scene), 2u);
  EXPECT_EQ(f.sectionBytes(SectionKind::Records), kWords * 4);
  EXPECT_FALSE(f.has(SectionKind::Leaves));
  for (uint32_t k = 0; k < f.header().sectionCount; ++k) EXPECT_EQ(f.header().sections[k].offset % compiled::kBlockBytes, 0u);
  char scene[2];
  f.read(SectionKind::Scene, 0, 2, scene);
  EXPECT_EQ(std::memcmp(scene, "{}", 2), 0);
  for (uint64_t w : {uint64_t(0), uint64_t(16383), uint64_t(16384), kWords - 1}) {
    uint32_t v;
    f.read(SectionKind::Records, w * 4, 4, &v);
    EXPECT_EQ(v, w);
  }
  // A range across two blocks.
  uint32_t pair[2];
  f.read(SectionKind::Records, 16383 * 4, 8, pair);
  EXPECT_EQ(pair[0], 16383u);
  EXPECT_EQ(pair[1], 16384u);
  // A range outside the section is refused, not read.
  uint32_t v;
  EXPECT_THROW(f.read(SectionKind::Records, kWords * 4 - 2, 4, &v), InputError);
}

TEST(CompiledFile, OpeningReadsNoDataBlock) {
  testing::TempFolder t;
  MappedFile f(writeSample(t), 0);
  EXPECT_EQ(f.stats().blocksVerified, 0u);
  EXPECT_EQ(f.stats().bytesRead, 0u);
  uint64_t v;
  f.read(SectionKind::Records, 60000 * 4, 8, &v);  // inside block 3
  EXPECT_EQ(f.stats().blocksVerified, 1u);
  EXPECT_EQ(f.stats().bytesRead, compiled::kBlockBytes);
}

TEST(CompiledFile, RefusesWhatIsNotOne) {
  testing::TempFolder t;
  EXPECT_NE(openError(t.write("x.rayes", "{\"camera\": {}}")).find("not a compiled Rayes scene"), std::string::npos);
  EXPECT_NE(openError(t.write("e.rayes", "")).find("not a compiled Rayes scene"), std::string::npos);
  EXPECT_NE(openError(t.path("missing.rayes")).find("cannot open"), std::string::npos);
}

TEST(CompiledFile, RefusesAnotherVersionNamingIt) {
  testing::TempFolder t;
  const std::string path = writeSample(t);
  // The format version's low byte: files of versions 1 (no meshes, uv sets or height maps)
  // 2 (no stored top level or shading rows) and 3 (forests as expanded patches), and one of a
  // later version.
  for (char version : {1, 2, 3, 5}) {
    patch(path, 8, version);
    const std::string e = openError(path);
    EXPECT_NE(e.find(":header: format version " + std::to_string(int(version))), std::string::npos) << e;
    EXPECT_NE(e.find("reads version 4"), std::string::npos) << e;
  }
}

TEST(CompiledFile, RefusesATruncatedFileAtEveryLength) {
  testing::TempFolder t;
  const std::string path = writeSample(t);
  const std::string bytes = t.read("s.rayes");
  for (size_t n : {size_t(9), size_t(600), size_t(4096), size_t(70000), bytes.size() - 1}) {
    const std::string cut = t.write("cut.rayes", bytes.substr(0, n));
    EXPECT_NE(openError(cut).find("truncated"), std::string::npos) << n << ": " << openError(cut);
  }
}

TEST(CompiledFile, RefusesACorruptHeaderOrChecksumSection) {
  testing::TempFolder t;
  const std::string path = writeSample(t);
  const std::string good = t.read("s.rayes");
  patch(path, 100, 'X');  // inside the program version
  EXPECT_NE(openError(path).find(":header: checksum mismatch"), std::string::npos) << openError(path);
  t.write("s.rayes", good);
  patch(path, good.size() - 1, char(good.back() ^ 1));  // the last block's CRC
  EXPECT_NE(openError(path).find(":section checksums: checksum mismatch"), std::string::npos) << openError(path);
}

TEST(CompiledFile, FindsACorruptBlockOnItsFirstTouchNamingIt) {
  testing::TempFolder t;
  const std::string path = writeSample(t);
  MappedFile probe(path, 0);
  const uint64_t records = probe.header().sections[1].offset;
  patch(path, records + 2 * compiled::kBlockBytes + 5, 'X');  // block 2
  MappedFile f(path, 0);  // opening reads no data block: it opens
  uint32_t v;
  EXPECT_NO_THROW(f.read(SectionKind::Records, 0, 4, &v));
  EXPECT_NO_THROW(f.read(SectionKind::Records, 3 * compiled::kBlockBytes, 4, &v));
  try {
    f.read(SectionKind::Records, 2 * compiled::kBlockBytes + 100, 4, &v, "leaf", 17);
    FAIL() << "the corrupt block was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.place(), "section records, block 2 (leaf 17)");
    EXPECT_NE(std::string(e.what()).find("checksum mismatch"), std::string::npos);
  }
}

TEST(CompiledFile, ABudgetKeepsTheMappingWithinItMeasured) {
  testing::TempFolder t;
  // 64 blocks of records, touched in turn three times under a budget of 8 blocks.
  const std::string path = t.path("big.rayes");
  {
    CompiledFileWriter w(path, "test");
    w.beginSection(SectionKind::Records);
    std::vector<uint8_t> block(compiled::kBlockBytes, 7);
    for (int b = 0; b < 64; ++b) w.write(block.data(), block.size());
    w.finish();
  }
  const uint64_t budget = 8 * compiled::kBlockBytes;
  MappedFile f(path, budget);
  uint64_t measuredPeak = 0, sum = 0;
  for (int pass = 0; pass < 3; ++pass)
    for (uint64_t b = 0; b < 64; ++b) {
      uint8_t byte;
      f.read(SectionKind::Records, b * compiled::kBlockBytes + 1000, 1, &byte);
      sum += byte;
      measuredPeak = std::max(measuredPeak, f.measuredResident());
    }
  EXPECT_EQ(sum, 3u * 64 * 7);  // the data never changes
  const MappedFileStats s = f.stats();
  EXPECT_LE(s.residentPeak, budget);
  EXPECT_EQ(s.bytesRead, 3u * 64 * compiled::kBlockBytes);  // every pass reads every block again
  EXPECT_GE(s.blocksReleased, 3u * 64 - 8);
  // The kernel's count: what the budget holds, plus the pages of the touch in progress.
  EXPECT_GT(measuredPeak, 0u);
  EXPECT_LE(measuredPeak, budget + compiled::kBlockBytes);
  // Without a budget nothing is released.
  MappedFile all(path, 0);
  for (uint64_t b = 0; b < 64; ++b) {
    uint8_t byte;
    all.read(SectionKind::Records, b * compiled::kBlockBytes, 1, &byte);
  }
  EXPECT_EQ(all.stats().blocksReleased, 0u);
  EXPECT_EQ(all.stats().residentPeak, 64 * compiled::kBlockBytes);
}

}  // namespace
}  // namespace rayes
