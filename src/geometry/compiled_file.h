// START HERE for compiled scenes. The .rayes file (docs/scene-format.md, "Compiled scenes"):
// a versioned container of page-aligned sections, written once by `rayes compile` and
// memory-mapped read-only by the render.
//
// Layout (little-endian): page 0 is the FileHeader (magic, format version, the program version
// that wrote it, the file's size, the block size, the section table, and a CRC-32 of the header
// and one of the checksum section). Every section starts on a block boundary (kBlockBytes, a
// multiple of the page); it is cut into blocks of kBlockBytes, and the checksum section (the file's last) holds one CRC-32 per block of every
// other section. Opening reads the header and the checksum section only (4 bytes per 64 KiB of
// data), so it costs O(file size / 16 Ki), never a read of the whole file; every other block is
// verified on its first touch.
//
// MappedFile: it owns the mapping (munmap on destruction) and hands out copies of ranges.
// Thread-safe: any thread may read any range at once.
// Residency (`--scene-memory`): read() marks the blocks it covers used; so does a gated read in
// place (gated(): core/gated_span.h, for tables read per ray, such as the top level's nodes);
// when the blocks counted resident exceed the budget, the least recently used ones (a clock:
// second chance) are released: madvise(MADV_COLD), where the kernel has it, puts their cached
// pages first in line for reclaim, and madvise(MADV_DONTNEED) drops them from the process (a
// read-only file mapping: read again from the file, or the page cache, on the next touch), so
// the data, and the render, never change. (MADV_PAGEOUT is not used: it skips the pages of a
// file the process may not write, so it cannot be what bounds the resident set.) The budget
// bounds what the mapping keeps; blocks being read at that moment (pinned: one record per
// thread) are not released, and may exceed it by a block or two per thread; a block a gated
// read maps again just after its release is released again when the clock next passes it and
// before stats() measures (core/gated_span.h). The mapping is placed at an address aligned
// to a block, so that the kernel's fault-around (which maps the cached pages of the 64 KiB
// window around a fault) maps pages of the touched block only, never strays of its neighbours
// that the budget would not count.
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <vector>
#include "core/gated_span.h"

namespace rayes {

namespace compiled {

constexpr char kMagic[8] = {'R', 'A', 'Y', 'E', 'S', 'S', 'C', 'N'};
// Version 4: sections Scene, Materials, Records, Leaves, Meshes (when a leaf is a subdivision
// face), UvSets (when a leaf has a uv set that a texture reads), Forests (when a leaf is a
// forest's: its record names the forest and the leaf, the section holds the forest's generator
// tables), TopLevel, LeafBoxes and LeafShading, Checksums; every position is in the render frame
// of the scene's camera (scene/scene.h, RenderFrame), whose world position the Scene section
// records ("frame_origin").
// Version 3 stored a forest's leaves as their expanded patch records (no Forests section);
// version 2 had no top level (the render built it) and its leaves were in world coordinates;
// version 1 had no subdivision faces, height maps or uv sets. A new section kind or a changed
// record is a new version; readers refuse others.
constexpr uint32_t kFormatVersion = 4;
constexpr uint64_t kPageBytes = 4096;
constexpr uint64_t kBlockBytes = 64 * 1024;  // a multiple of the page: released whole
constexpr int kMaxSections = 16;

enum class SectionKind : uint32_t {
  Scene = 1,      // JSON: the scene's text (camera, film, materials, lights), its source path, the leaf kinds' names
  Materials = 2,  // uint32 per leaf: its material
  Leaves = 3,     // LeafEntry per leaf
  Records = 4,    // patch records (geometry/patch_record.h), at the LeafEntry's offsets
  Checksums = 5,  // uint32 CRC-32 per block of every other section, in section order
  Meshes = 6,     // subdivision topologies and meshes' control points (the Scene section indexes them)
  UvSets = 7,     // the leaves' uv sets (scene/leaf_uv_table.h): a UvRef per leaf, then UvCorners
  TopLevel = 8,   // the top-level BVH's 128-byte nodes (toplevel/toplevel_node.h), depth first; its root in the Scene section
  LeafBoxes = 9,  // Box3 per leaf of the render (the shapes' leaves, then the lights'): what the top level was built over
  LeafShading = 10,  // 16 bytes per leaf of the render: material, box side, dicing error, shading rank (shading/shading_scene.h)
  Forests = 11,   // per forest (the Scene section indexes them): a ForestHeader, its branches, its foliage
};
const char* sectionName(SectionKind kind);

struct SectionEntry {
  uint32_t kind = 0, reserved = 0;
  uint64_t offset = 0, bytes = 0;
  uint64_t firstBlock = 0;  // index of its first block's CRC in the checksum section
};

struct FileHeader {
  char magic[8];
  uint32_t formatVersion;
  uint32_t headerBytes;  // sizeof(FileHeader)
  char program[64];      // the writing program's version, NUL-terminated
  uint64_t fileBytes;
  uint64_t blockBytes;
  uint32_t sectionCount;
  uint32_t checksumsCrc;  // of the checksum section
  uint32_t headerCrc;     // of this header with headerCrc = 0
  uint32_t reserved;
  SectionEntry sections[kMaxSections];
};
static_assert(sizeof(FileHeader) <= kPageBytes);

// One leaf of the table: everything a render asks before dicing (LeafSource::bounds, facts)
// and where the leaf's patch record lies in the Records section.
struct LeafEntry {
  float lo[3], hi[3];  // Box3
  float sizeBound, dicingError;
  uint64_t recordOffset;
  uint32_t recordBytes;
  uint16_t timeSamples;
  uint8_t kind;   // index into the Scene section's "kinds"
  uint8_t flags;  // kDisplaced | kSubdivision | kBorderClosure
  static constexpr uint8_t kDisplaced = 1, kSubdivision = 2, kBorderClosure = 4;
};
static_assert(sizeof(LeafEntry) == 48);

// A leaf's uv set in the UvSets section: table 0 none, 1 the corners at `index` (four (s, t)
// as 8 floats, after the section's refs), t >= 2 leaf `index` of the uv set of topology t - 2
// (the Scene section's "topologies").
struct UvRef {
  uint32_t table = 0, index = 0;
};
static_assert(sizeof(UvRef) == 8);

// The TopLevel section's first 128 bytes; the nodes follow (so none straddles a block).
struct TopLevelHeader {
  uint64_t nodeCount = 0, leafCount = 0;
  uint32_t root = 0, nodeBytes = 0;
  uint32_t reserved[26] = {};
};
static_assert(sizeof(TopLevelHeader) == 128);

// A forest's generator tables in the Forests section: this header (its ForestParams, field by
// field), then branchCount ForestBranch (76 bytes each) and foliageCount ForestFoliage (36 bytes
// each), as geometry/forest_patches.h lays them out; read in place by the render.
struct ForestHeader {
  uint64_t seed = 0;
  uint64_t branchCount = 0, foliageCount = 0;
  uint32_t trees = 0;
  int32_t detail = 0, branching = 0, terrainTiles = 0, leavesPerTwig = 0;
  float area = 0, treeHeight = 0, terrainAmplitude = 0;
  float placement[3][4] = {};  // Transform::m
  uint32_t reserved[6] = {};
};
static_assert(sizeof(ForestHeader) == 128);

// A top level to store, built by the caller (app/compile_command.cpp: this folder knows no BVH).
struct StoredTopLevel {
  const void* nodes = nullptr;  // nodeCount nodes of nodeBytes each
  uint64_t nodeCount = 0;
  uint32_t nodeBytes = 0;
  uint32_t root = 0;
  const void* leafBoxes = nullptr;  // leafCount Box3 (24 bytes each)
  uint64_t leafCount = 0;
};

}  // namespace compiled

// Writes a .rayes file section by section, in one pass (CRCs computed as the bytes go by).
// Failures throw InputError naming the file (ResourceError "-o" when the disk is full).
class CompiledFileWriter {
 public:
  CompiledFileWriter(const std::string& path, const std::string& programVersion);
  ~CompiledFileWriter();
  CompiledFileWriter(const CompiledFileWriter&) = delete;
  CompiledFileWriter& operator=(const CompiledFileWriter&) = delete;
  void beginSection(compiled::SectionKind kind);
  void write(const void* data, size_t bytes);
  uint64_t sectionBytes() const { return at_ - sectionStart_; }
  // Writes the checksum section and the header, and closes the file.
  void finish();

 private:
  void raw(const void* data, size_t bytes);
  void padToPage();
  void endSection();
  void fail(const char* doing);

  std::string path_;
  std::FILE* file_ = nullptr;
  compiled::FileHeader header_{};
  std::vector<uint32_t> crcs_;
  uint64_t at_ = 0, sectionStart_ = 0;
  bool inSection_ = false;
  uint32_t blockCrc_ = 0;
  uint64_t blockFill_ = 0;
};

// What the mapping did, for the stats ("scene.compiled", docs/stats.md).
struct MappedFileStats {
  uint64_t bytesMapped = 0;
  uint64_t residentPeak = 0;  // the largest resident estimate (blocks touched and not released)
  uint64_t bytesRead = 0;     // blocks made resident, counted again after each release
  uint64_t blocksVerified = 0, blocksReleased = 0;
  uint64_t budget = 0;        // 0: none
  uint64_t residentAtEnd = 0; // measured (MappedFile::measuredResident) when the stats were read
};

class MappedFile {
 public:
  // Maps `path` and checks the header, the section table and the checksum section; throws
  // InputError(path, place, why) for a file that is not a .rayes, of another version,
  // truncated or corrupt. residentBudget 0: no budget (nothing is released).
  MappedFile(const std::string& path, uint64_t residentBudget);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  const std::string& path() const { return path_; }
  const compiled::FileHeader& header() const { return header_; }
  bool has(compiled::SectionKind kind) const;
  uint64_t sectionBytes(compiled::SectionKind kind) const;
  // Copies bytes [at, at + n) of a section to `out`, verified (a corrupt block: InputError
  // naming the file, the section, the block and `what`, e.g. "leaf 12") and marked used. The
  // blocks are pinned while they are read, so no other thread releases them meanwhile: what
  // the kernel maps is always what the budget counts.
  void read(compiled::SectionKind kind, uint64_t at, uint64_t n, void* out, const char* what = "",
            uint64_t whatIndex = 0) const;
  MappedFileStats stats() const;
  uint64_t residentPeak() const { return residentPeak_.load(std::memory_order_relaxed); }
  // The mapping's resident bytes as the kernel counts them now (Rss of its /proc/self/smaps
  // entry; 0 where that cannot be read): what the budget bounds, measured.
  uint64_t measuredResident() const;

  // A section's bytes to read in place through its gate (core/gated_span.h): every block is
  // verified on its first touch (InputError naming the file, the section and the block) and
  // counted against the budget like read()'s. `data` is block-aligned.
  struct GatedSection {
    const uint8_t* data = nullptr;
    uint64_t bytes = 0;
    const BlockGate* gate = nullptr;
  };
  GatedSection gated(compiled::SectionKind kind) const;

 private:
  class SectionGate;
  void admit(const compiled::SectionEntry& s, uint64_t block) const;  // a gate's slow path
  void release(uint64_t block) const;                                 // madvise, under the lock
  const compiled::SectionEntry& section(compiled::SectionKind kind) const;
  void use(uint64_t block) const;  // residency bookkeeping
  uint64_t windowBytes(uint64_t block) const;
  void verify(const compiled::SectionEntry& s, uint64_t block, const char* what, uint64_t whatIndex) const;

  std::string path_;
  const uint8_t* base_ = nullptr;
  uint64_t size_ = 0;
  compiled::FileHeader header_{};
  std::vector<uint32_t> crcs_;
  uint64_t budget_ = 0;
  // Per block (global index, as in the checksum section): verified once; resident and
  // referenced for the clock.
  std::unique_ptr<std::atomic<uint8_t>[]> verified_, resident_, referenced_;
  std::unique_ptr<std::atomic<uint32_t>[]> pinned_;  // readers in the block now
  // Per block: verified, resident and referenced since the clock last passed (the gates' fast path).
  std::unique_ptr<std::atomic<uint8_t>[]> ready_;
  std::vector<std::unique_ptr<SectionGate>> gates_;  // by section table index
  std::vector<uint64_t> blockStart_;  // file offset of each block, and its length
  std::vector<uint32_t> blockLength_;
  mutable std::mutex residency_;
  mutable uint64_t hand_ = 0;
  mutable uint64_t residentBytes_ = 0;
  mutable std::atomic<uint64_t> residentPeak_{0}, bytesRead_{0}, blocksVerified_{0}, blocksReleased_{0};
};

}  // namespace rayes
