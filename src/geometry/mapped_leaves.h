// A compiled scene's leaves as a LeafSource (geometry/leaf_source.h): the leaf table and the
// patch records of a memory-mapped .rayes file (geometry/compiled_file.h). bounds(i) and
// facts(i) read leaf i's 48-byte entry; patch(i) decodes its record (geometry/patch_record.h)
// into a new Patch, which the caller drops after dicing, like a forest's generated leaves. A
// record's bytes are touched only then, so what stays resident is bounded by the mapping's
// budget (--scene-memory), never by the scene.
//
// Errors found on first touch (a block's checksum, a record that does not decode) are
// InputError naming the file, the section and block or the leaf: they may surface mid-render.
// Shares ownership of the mapping; immutable; every const method is thread-safe.
#pragma once
#include <memory>
#include <string>
#include <vector>
#include "geometry/compiled_file.h"
#include "geometry/leaf_source.h"
#include "geometry/patch_record.h"

namespace rayes {

class MappedLeaves final : public LeafSource {
 public:
  // `kinds`: the names the entries' kind indices refer to (the Scene section's "kinds");
  // `shared`: the meshes and height maps records name (filled by the loader before the first
  // patch(), never changed after). Throws InputError when the leaf table's size is not a whole
  // number of entries.
  MappedLeaves(std::shared_ptr<const MappedFile> file, std::vector<std::string> kinds,
               std::shared_ptr<const RecordTables> shared = nullptr);
  MappedLeaves(const MappedLeaves&) = delete;  // facts point into kinds_
  MappedLeaves& operator=(const MappedLeaves&) = delete;
  size_t size() const override { return size_; }
  Box3 bounds(size_t i) const override;
  PatchPtr patch(size_t i) const override;
  LeafFacts facts(size_t i) const override;
  // What the mapping holds resident at its peak (the entries and records touched and not
  // released), plus the kinds' names: the description's share of the process's memory.
  size_t descriptionBytes() const override;
  const MappedFile& file() const { return *file_; }

 private:
  compiled::LeafEntry entry(size_t i) const;
  std::shared_ptr<const MappedFile> file_;
  std::vector<std::string> kinds_;
  std::shared_ptr<const RecordTables> shared_;
  size_t size_ = 0;
};

}  // namespace rayes
