#include "geometry/mapped_leaves.h"
#include <cstring>
#include <stdexcept>
#include "core/error.h"
#include "geometry/patch_record.h"

namespace rayes {

using compiled::LeafEntry;
using compiled::SectionKind;

MappedLeaves::MappedLeaves(std::shared_ptr<const MappedFile> file, std::vector<std::string> kinds,
                           std::shared_ptr<const RecordTables> shared)
    : file_(std::move(file)), kinds_(std::move(kinds)), shared_(std::move(shared)) {
  const uint64_t bytes = file_->sectionBytes(SectionKind::Leaves);
  if (bytes % sizeof(LeafEntry) != 0)
    throw InputError(file_->path(), "section leaves", "its size is not a whole number of 48-byte leaf entries");
  size_ = size_t(bytes / sizeof(LeafEntry));
}

LeafEntry MappedLeaves::entry(size_t i) const {
  LeafEntry e;
  file_->read(SectionKind::Leaves, uint64_t(i) * sizeof(LeafEntry), sizeof(LeafEntry), &e, "leaf", i);
  if (e.kind >= kinds_.size())
    throw InputError(file_->path(), "section leaves (leaf " + std::to_string(i) + ")", "an unknown kind index");
  return e;
}

Box3 MappedLeaves::bounds(size_t i) const {
  const LeafEntry e = entry(i);
  Box3 b;
  b.lo = {e.lo[0], e.lo[1], e.lo[2]};
  b.hi = {e.hi[0], e.hi[1], e.hi[2]};
  return b;
}

LeafFacts MappedLeaves::facts(size_t i) const {
  const LeafEntry e = entry(i);
  LeafFacts f;
  f.sizeBound = e.sizeBound;
  f.dicingError = e.dicingError;
  f.timeSamples = e.timeSamples;
  f.kind = kinds_[e.kind].c_str();
  f.displaced = e.flags & LeafEntry::kDisplaced;
  f.subdivision = e.flags & LeafEntry::kSubdivision;
  f.borderClosure = e.flags & LeafEntry::kBorderClosure;
  return f;
}

PatchPtr MappedLeaves::patch(size_t i) const {
  const LeafEntry e = entry(i);
  // Records are small (a Bézier patch 193 bytes): copied out, decoded from the copy.
  thread_local std::vector<uint8_t> record;
  record.resize(e.recordBytes);
  file_->read(SectionKind::Records, e.recordOffset, e.recordBytes, record.data(), "leaf", i);
  try {
    return decodePatch(record.data(), e.recordBytes, shared_.get());
  } catch (const std::invalid_argument& x) {
    throw InputError(file_->path(), "section records (leaf " + std::to_string(i) + ")",
                     std::string("the patch record does not decode: ") + x.what());
  }
}

size_t MappedLeaves::descriptionBytes() const {
  size_t bytes = size_t(file_->residentPeak());
  for (const std::string& k : kinds_) bytes += k.capacity();
  return bytes;
}

}  // namespace rayes
