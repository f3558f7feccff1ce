#include "geometry/compiled_file.h"
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>
#include "core/error.h"

namespace rayes {

using namespace compiled;

const char* compiled::sectionName(SectionKind kind) {
  switch (kind) {
    case SectionKind::Scene: return "scene";
    case SectionKind::Materials: return "materials";
    case SectionKind::Leaves: return "leaves";
    case SectionKind::Records: return "records";
    case SectionKind::Checksums: return "checksums";
    case SectionKind::Meshes: return "meshes";
    case SectionKind::UvSets: return "uv_sets";
    case SectionKind::TopLevel: return "top_level";
    case SectionKind::LeafBoxes: return "leaf_boxes";
    case SectionKind::LeafShading: return "leaf_shading";
    case SectionKind::Forests: return "forests";
  }
  return "unknown";
}

namespace {

uint32_t crcOf(const void* data, uint64_t bytes, uint32_t crc = 0) {
  const auto* p = static_cast<const Bytef*>(data);
  while (bytes > 0) {
    const uInt n = uInt(std::min<uint64_t>(bytes, uint64_t(1) << 30));
    crc = uint32_t(crc32(crc, p, n));
    p += n;
    bytes -= n;
  }
  return crc;
}

uint32_t headerCrcOf(FileHeader h) {
  h.headerCrc = 0;
  return crcOf(&h, sizeof h);
}

uint64_t blocksOf(uint64_t bytes) { return (bytes + kBlockBytes - 1) / kBlockBytes; }

// A bit of a block's `verified_` byte (bit 0: verified): released by the clock, and not counted
// resident since, so a gated read may have mapped it again uncounted.
constexpr uint8_t kMaybeStray = 2;

}  // namespace

// ---- writing

CompiledFileWriter::CompiledFileWriter(const std::string& path, const std::string& programVersion) : path_(path) {
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_) fail("cannot create it");
  std::memcpy(header_.magic, kMagic, sizeof kMagic);
  header_.formatVersion = kFormatVersion;
  header_.headerBytes = sizeof(FileHeader);
  std::snprintf(header_.program, sizeof header_.program, "%s", programVersion.c_str());
  header_.blockBytes = kBlockBytes;
  padToPage();  // page 0: the header, written last
}

CompiledFileWriter::~CompiledFileWriter() {
  if (file_) std::fclose(file_);
}

void CompiledFileWriter::fail(const char* doing) {
  const int e = errno;
  if (file_) std::fclose(file_);
  file_ = nullptr;
  if (e == ENOSPC || e == EDQUOT) throw ResourceError("-o", path_ + ": " + doing + ": " + std::strerror(e) + " (free disk space)");
  throw InputError(path_, "", std::string(doing) + ": " + std::strerror(e));
}

void CompiledFileWriter::raw(const void* data, size_t bytes) {
  if (bytes && std::fwrite(data, 1, bytes, file_) != bytes) fail("cannot write it");
  at_ += bytes;
}

// Sections start on block boundaries (so blocks are whole windows of the mapping; see the header).
void CompiledFileWriter::padToPage() {
  static const uint8_t zeros[kPageBytes] = {};
  uint64_t pad = (kBlockBytes - at_ % kBlockBytes) % kBlockBytes;
  if (at_ == 0) pad = kBlockBytes;  // the header's block
  while (pad > 0) {
    const uint64_t n = std::min<uint64_t>(pad, kPageBytes);
    raw(zeros, n);
    pad -= n;
  }
}

void CompiledFileWriter::beginSection(SectionKind kind) {
  if (inSection_) endSection();
  if (header_.sectionCount + 1 >= uint32_t(kMaxSections)) throw std::logic_error("too many sections");
  padToPage();
  SectionEntry& s = header_.sections[header_.sectionCount++];
  s.kind = uint32_t(kind);
  s.offset = at_;
  s.firstBlock = crcs_.size();
  sectionStart_ = at_;
  inSection_ = true;
  blockCrc_ = 0;
  blockFill_ = 0;
}

void CompiledFileWriter::write(const void* data, size_t bytes) {
  const auto* p = static_cast<const uint8_t*>(data);
  while (bytes > 0) {
    const size_t n = size_t(std::min<uint64_t>(bytes, kBlockBytes - blockFill_));
    blockCrc_ = crcOf(p, n, blockCrc_);
    raw(p, n);
    blockFill_ += n;
    if (blockFill_ == kBlockBytes) {
      crcs_.push_back(blockCrc_);
      blockCrc_ = 0;
      blockFill_ = 0;
    }
    p += n;
    bytes -= n;
  }
}

void CompiledFileWriter::endSection() {
  if (blockFill_ > 0) crcs_.push_back(blockCrc_);
  blockFill_ = 0;
  header_.sections[header_.sectionCount - 1].bytes = at_ - sectionStart_;
  inSection_ = false;
}

void CompiledFileWriter::finish() {
  if (inSection_) endSection();
  padToPage();
  SectionEntry& s = header_.sections[header_.sectionCount++];
  s.kind = uint32_t(SectionKind::Checksums);
  s.offset = at_;
  s.bytes = crcs_.size() * sizeof(uint32_t);
  s.firstBlock = crcs_.size();
  raw(crcs_.data(), crcs_.size() * sizeof(uint32_t));
  header_.checksumsCrc = crcOf(crcs_.data(), crcs_.size() * sizeof(uint32_t));
  header_.fileBytes = at_;
  header_.headerCrc = headerCrcOf(header_);
  if (std::fseek(file_, 0, SEEK_SET) != 0) fail("cannot write its header");
  if (std::fwrite(&header_, 1, sizeof header_, file_) != sizeof header_) fail("cannot write its header");
  if (std::fflush(file_) != 0 || fsync(fileno(file_)) != 0) fail("cannot write it");
  const int rc = std::fclose(file_);
  file_ = nullptr;
  if (rc != 0) fail("cannot close it");
}

// ---- reading

class MappedFile::SectionGate final : public BlockGate {
 public:
  SectionGate(const MappedFile& file, const SectionEntry& s) : BlockGate(&file.ready_[s.firstBlock]), file_(file), s_(s) {}
  void admit(uint64_t block) const override { file_.admit(s_, block); }

 private:
  const MappedFile& file_;
  const SectionEntry& s_;
};

MappedFile::MappedFile(const std::string& path, uint64_t residentBudget) : path_(path), budget_(residentBudget) {
  const auto bad = [&](const std::string& place, const std::string& why) { throw InputError(path_, place, why); };
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) bad("", std::string("cannot open the compiled scene: ") + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    bad("", "not a regular file");
  }
  size_ = uint64_t(st.st_size);
  if (size_ > 0) {
    // A block-aligned address: reserve a block more than the file, map the file over the
    // aligned part of the reservation, return the rest.
    const auto fail = [&] {
      const int e = errno;
      ::close(fd);
      bad("", std::string("cannot map the compiled scene: ") + std::strerror(e));
    };
    void* r = ::mmap(nullptr, size_ + kBlockBytes, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (r == MAP_FAILED) fail();
    const uintptr_t start = reinterpret_cast<uintptr_t>(r);
    const uintptr_t aligned = (start + kBlockBytes - 1) / kBlockBytes * kBlockBytes;
    void* m = ::mmap(reinterpret_cast<void*>(aligned), size_, PROT_READ, MAP_SHARED | MAP_FIXED, fd, 0);
    if (m == MAP_FAILED) {
      ::munmap(r, size_ + kBlockBytes);
      fail();
    }
    if (aligned > start) ::munmap(r, aligned - start);
    const uintptr_t mapEnd = (aligned + size_ + kPageBytes - 1) / kPageBytes * kPageBytes;
    if (start + size_ + kBlockBytes > mapEnd) ::munmap(reinterpret_cast<void*>(mapEnd), start + size_ + kBlockBytes - mapEnd);
    base_ = static_cast<const uint8_t*>(m);
  }
  // Pages of the file already cached (by the compile that wrote it, or another reader's
  // read-ahead) may sit in large folios, which a fault maps whole, past the block touched and
  // outside what the budget counts; dropped from the cache (clean pages: nothing is lost), they
  // come back page by page, a block at a time (read()).
  ::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);
  ::close(fd);
  if (size_ < sizeof kMagic || std::memcmp(base_, kMagic, sizeof kMagic) != 0)
    bad("", "not a compiled Rayes scene (no RAYESSCN magic at its start; make one with rayes compile SCENE.json -o SCENE.rayes)");
  if (size_ < sizeof(FileHeader)) bad("header", "truncated: " + std::to_string(size_) + " bytes, less than the header");
  std::memcpy(&header_, base_, sizeof header_);
  if (header_.formatVersion != kFormatVersion)
    bad("header", "format version " + std::to_string(header_.formatVersion) + ", written by rayes " +
                      std::string(header_.program, strnlen(header_.program, sizeof header_.program)) +
                      "; this program reads version " + std::to_string(kFormatVersion) +
                      ": compile the scene again with this program");
  if (header_.headerBytes != sizeof(FileHeader) || headerCrcOf(header_) != header_.headerCrc)
    bad("header", "checksum mismatch: the header is corrupt; compile the scene again");
  if (header_.fileBytes != size_)
    bad("header", "truncated or extended: the file has " + std::to_string(size_) + " bytes, its header says " +
                      std::to_string(header_.fileBytes));
  if (header_.blockBytes != kBlockBytes || header_.sectionCount < 1 || header_.sectionCount > uint32_t(kMaxSections))
    bad("header", "an impossible block size or section count");
  // The section table: in order, page-aligned, inside the file; the last one the checksums.
  uint64_t blocks = 0, end = kBlockBytes;
  for (uint32_t k = 0; k < header_.sectionCount; ++k) {
    const SectionEntry& s = header_.sections[k];
    const std::string place = "section " + std::to_string(k);
    if (s.offset % kBlockBytes != 0 || s.offset < end || s.bytes > size_ || s.offset > size_ - s.bytes)
      bad(place, "lies outside the file or out of order");
    end = s.offset + s.bytes;
    if (k + 1 < header_.sectionCount) {
      if (s.firstBlock != blocks) bad(place, "its checksums are out of order");
      blocks += blocksOf(s.bytes);
    }
  }
  const SectionEntry& sums = header_.sections[header_.sectionCount - 1];
  if (sums.kind != uint32_t(SectionKind::Checksums) || sums.bytes != blocks * sizeof(uint32_t))
    bad("section checksums", "missing, or not one per block");
  crcs_.resize(blocks);
  if (sums.bytes != 0) std::memcpy(crcs_.data(), base_ + sums.offset, sums.bytes);
  if (crcOf(crcs_.data(), sums.bytes) != header_.checksumsCrc)
    bad("section checksums", "checksum mismatch: the checksum section is corrupt; compile the scene again");

  verified_.reset(new std::atomic<uint8_t>[blocks]());
  resident_.reset(new std::atomic<uint8_t>[blocks]());
  referenced_.reset(new std::atomic<uint8_t>[blocks]());
  pinned_.reset(new std::atomic<uint32_t>[blocks]());
  ready_.reset(new std::atomic<uint8_t>[blocks]());
  blockStart_.resize(blocks);
  blockLength_.resize(blocks);
  for (uint32_t k = 0; k + 1 < header_.sectionCount; ++k) {
    const SectionEntry& s = header_.sections[k];
    for (uint64_t b = 0; b < blocksOf(s.bytes); ++b) {
      blockStart_[s.firstBlock + b] = s.offset + b * kBlockBytes;
      blockLength_[s.firstBlock + b] = uint32_t(std::min<uint64_t>(kBlockBytes, s.bytes - b * kBlockBytes));
    }
  }
  for (uint32_t k = 0; k + 1 < header_.sectionCount; ++k) gates_.push_back(std::make_unique<SectionGate>(*this, header_.sections[k]));
  // Pages are read when a block is touched, not ahead of it (a render touches leaves in the
  // order of its rays, not of the file); what was read for the header goes back.
  ::madvise(const_cast<uint8_t*>(base_), size_, MADV_RANDOM);
  ::madvise(const_cast<uint8_t*>(base_), kBlockBytes, MADV_DONTNEED);
  const uint64_t sumsPage = sums.offset / kPageBytes * kPageBytes;
  ::madvise(const_cast<uint8_t*>(base_) + sumsPage, size_ - sumsPage, MADV_DONTNEED);
}

// A block's window of the mapping: the block and, after a section's last (partial) block, the
// padding to the next section, which the kernel's fault-around maps with it. Counted and
// released whole.
uint64_t MappedFile::windowBytes(uint64_t g) const {
  const uint64_t mapped = (size_ + kPageBytes - 1) / kPageBytes * kPageBytes;
  return std::min<uint64_t>(kBlockBytes, mapped - blockStart_[g]);
}

MappedFile::~MappedFile() {
  gates_.clear();
  if (base_) ::munmap(const_cast<uint8_t*>(base_), size_);
}

const SectionEntry& MappedFile::section(SectionKind kind) const {
  for (uint32_t k = 0; k < header_.sectionCount; ++k)
    if (header_.sections[k].kind == uint32_t(kind)) return header_.sections[k];
  throw InputError(path_, "header", std::string("no ") + sectionName(kind) + " section");
}

bool MappedFile::has(SectionKind kind) const {
  for (uint32_t k = 0; k < header_.sectionCount; ++k)
    if (header_.sections[k].kind == uint32_t(kind)) return true;
  return false;
}

uint64_t MappedFile::sectionBytes(SectionKind kind) const { return section(kind).bytes; }

MappedFile::GatedSection MappedFile::gated(SectionKind kind) const {
  const SectionEntry& s = section(kind);
  return {base_ + s.offset, s.bytes, gates_[size_t(&s - header_.sections)].get()};
}

// As read(), without the pin: a reader in place holds no pin (see core/gated_span.h for what
// that leaves uncounted).
void MappedFile::admit(const SectionEntry& s, uint64_t block) const {
  const uint64_t g = s.firstBlock + block;
  if (block >= blocksOf(s.bytes)) throw std::logic_error("MappedFile: a gated read past its section");
  if (!resident_[g].load(std::memory_order_relaxed))
    ::madvise(const_cast<uint8_t*>(base_) + blockStart_[g], windowBytes(g), MADV_WILLNEED);
  if (!verified_[g].load(std::memory_order_acquire)) verify(s, block, "", 0);
  use(g);
  // Under the lock, and only while it is still counted: a release between use() and this store
  // would otherwise leave the block ready, read on the fast path, and never counted again.
  std::lock_guard lock(residency_);
  if (resident_[g].load(std::memory_order_relaxed)) ready_[g].store(1, std::memory_order_relaxed);
}

void MappedFile::release(uint64_t h) const {
  uint8_t* p = const_cast<uint8_t*>(base_) + blockStart_[h];
#ifdef MADV_COLD
  ::madvise(p, windowBytes(h), MADV_COLD);  // EINVAL before Linux 5.4: the hint is lost, nothing else
#endif
  ::madvise(p, windowBytes(h), MADV_DONTNEED);
}

void MappedFile::verify(const SectionEntry& s, uint64_t block, const char* what, uint64_t whatIndex) const {
  const uint64_t g = s.firstBlock + block;
  if (crcOf(base_ + blockStart_[g], blockLength_[g]) != crcs_[g]) {
    std::string place = std::string("section ") + sectionName(SectionKind(s.kind)) + ", block " + std::to_string(block);
    if (*what) place += " (" + std::string(what) + " " + std::to_string(whatIndex) + ")";
    throw InputError(path_, place, "checksum mismatch: the file is corrupt; compile the scene again");
  }
  uint8_t expected = 0;
  if (verified_[g].compare_exchange_strong(expected, 1)) blocksVerified_.fetch_add(1, std::memory_order_relaxed);
}

void MappedFile::read(SectionKind kind, uint64_t at, uint64_t n, void* out, const char* what, uint64_t whatIndex) const {
  const SectionEntry& s = section(kind);
  if (n == 0) return;
  if (at > s.bytes || n > s.bytes - at) {
    std::string place = std::string("section ") + sectionName(kind);
    if (*what) place += " (" + std::string(what) + " " + std::to_string(whatIndex) + ")";
    throw InputError(path_, place, "bytes [" + std::to_string(at) + ", " + std::to_string(at + n) +
                                       ") lie outside the section: the file is corrupt");
  }
  const uint64_t b0 = at / kBlockBytes, b1 = (at + n - 1) / kBlockBytes;
  const auto unpin = [&](uint64_t last) {
    for (uint64_t b = b0; b <= last; ++b) pinned_[s.firstBlock + b].fetch_sub(1, std::memory_order_seq_cst);
  };
  for (uint64_t b = b0; b <= b1; ++b) {
    const uint64_t g = s.firstBlock + b;
    pinned_[g].fetch_add(1, std::memory_order_seq_cst);
    try {
      if (!resident_[g].load(std::memory_order_relaxed))  // one read of the block, not a fault per page
        ::madvise(const_cast<uint8_t*>(base_) + blockStart_[g], windowBytes(g), MADV_WILLNEED);
      if (!verified_[g].load(std::memory_order_acquire)) verify(s, b, what, whatIndex);
    } catch (...) {
      unpin(b);
      throw;
    }
    use(g);
  }
  if (n != 0) std::memcpy(out, base_ + s.offset + at, n);
  unpin(b1);
}

// Called with g pinned. A release (below) clears `resident` before it looks at the pins, and a
// reader pins before it looks at `resident` (both sequentially consistent): so either the
// reader sees the block released and counts it again under the lock, or the release sees the
// pin and keeps the block.
void MappedFile::use(uint64_t g) const {
  if (resident_[g].load(std::memory_order_seq_cst)) {
    referenced_[g].store(1, std::memory_order_relaxed);
    return;
  }
  std::lock_guard lock(residency_);
  referenced_[g].store(1, std::memory_order_relaxed);
  if (resident_[g].load(std::memory_order_seq_cst)) return;
  resident_[g].store(1, std::memory_order_seq_cst);
  verified_[g].fetch_and(uint8_t(~kMaybeStray), std::memory_order_relaxed);  // counted again
  residentBytes_ += windowBytes(g);
  bytesRead_.fetch_add(windowBytes(g), std::memory_order_relaxed);
  // The clock: a block touched since the hand last passed gets a second chance; the first
  // one not touched (nor being read) is released. Two sweeps find one unless every block is
  // in use.
  const uint64_t blocks = crcs_.size();
  for (uint64_t step = 0; budget_ > 0 && residentBytes_ > budget_ && step < 2 * blocks; ++step) {
    hand_ = hand_ + 1 < blocks ? hand_ + 1 : 0;
    const uint64_t h = hand_;
    if (h == g) continue;
    if (!resident_[h].load(std::memory_order_relaxed)) {
      // A released block a gated read may have mapped again uncounted (core/gated_span.h):
      // released again as the hand passes, so such pages never outlive a turn of the clock.
      if (verified_[h].load(std::memory_order_relaxed) & kMaybeStray) {
        verified_[h].fetch_and(uint8_t(~kMaybeStray), std::memory_order_relaxed);
        release(h);
      }
      continue;
    }
    if (referenced_[h].exchange(0, std::memory_order_relaxed)) {
      ready_[h].store(0, std::memory_order_relaxed);  // a gated read marks it again
      continue;
    }
    resident_[h].store(0, std::memory_order_seq_cst);
    if (pinned_[h].load(std::memory_order_seq_cst) > 0) {
      resident_[h].store(1, std::memory_order_seq_cst);
      continue;
    }
    ready_[h].store(0, std::memory_order_seq_cst);
    release(h);
    verified_[h].fetch_or(kMaybeStray, std::memory_order_relaxed);
    residentBytes_ -= windowBytes(h);
    blocksReleased_.fetch_add(1, std::memory_order_relaxed);
  }
  if (residentBytes_ > residentPeak_.load(std::memory_order_relaxed)) residentPeak_.store(residentBytes_, std::memory_order_relaxed);
}

MappedFileStats MappedFile::stats() const {
  {
    // Strays a gated read mapped again after their release, and the hand has not passed
    // since, are released now: what the kernel counts below is what the budget counted.
    std::lock_guard lock(residency_);
    for (uint64_t h = 0; h < crcs_.size(); ++h)
      if (!resident_[h].load(std::memory_order_relaxed) && (verified_[h].load(std::memory_order_relaxed) & kMaybeStray)) {
        verified_[h].fetch_and(uint8_t(~kMaybeStray), std::memory_order_relaxed);
        release(h);
      }
  }
  MappedFileStats s;
  s.bytesMapped = size_;
  s.residentPeak = residentPeak_.load();
  s.bytesRead = bytesRead_.load();
  s.blocksVerified = blocksVerified_.load();
  s.blocksReleased = blocksReleased_.load();
  s.budget = budget_;
  s.residentAtEnd = measuredResident();
  return s;
}

uint64_t MappedFile::measuredResident() const {
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    // A mapping's first line: "start-end perms offset dev inode path".
    const size_t dash = line.find('-');
    if (dash != std::string::npos && dash > 0 && line.find(' ') > dash && std::isxdigit(static_cast<unsigned char>(line[0]))) {
      inside = std::stoull(line.substr(0, dash), nullptr, 16) == reinterpret_cast<uintptr_t>(base_);
      continue;
    }
    if (inside && line.rfind("Rss:", 0) == 0) return std::stoull(line.substr(4)) * 1024;
  }
  return 0;
}

}  // namespace rayes
