#include "shading/brick_grid.h"
#include <algorithm>
#include <atomic>

namespace rayes {
namespace {
std::atomic<uint32_t> nextGridId{0};
}  // namespace

BrickGrid::BrickGrid(std::shared_ptr<const BrickSource> source)
    : id_(nextGridId.fetch_add(1, std::memory_order_relaxed)), source_(std::move(source)) {}

void BrickGrid::addResident(BrickCoord c, const BrickVoxels& voxels) {
  coords_.push_back(c);
  kind_.push_back(Kind::Resident);
  index_.push_back(uint32_t(resident_.size()));
  value_.push_back(*std::max_element(voxels.begin(), voxels.end()));
  resident_.push_back(voxels);
}

void BrickGrid::addStored(BrickCoord c, uint32_t stored, float maxVoxel) {
  coords_.push_back(c);
  kind_.push_back(Kind::Stored);
  index_.push_back(stored);
  value_.push_back(maxVoxel);
  ++stored_;
}

void BrickGrid::addConstant(BrickCoord c, float value) {
  coords_.push_back(c);
  kind_.push_back(Kind::Constant);
  index_.push_back(0);
  value_.push_back(value);
}

int32_t BrickGrid::brickAt(int32_t cx, int32_t cy, int32_t cz) const {
  const int64_t x = int64_t(cx) - cellLo_.x, y = int64_t(cy) - cellLo_.y, z = int64_t(cz) - cellLo_.z;
  if (x < 0 || y < 0 || z < 0 || x >= cellCount_.x || y >= cellCount_.y || z >= cellCount_.z) return -1;
  return cells_[size_t((x * cellCount_.y + y) * cellCount_.z + z)];
}

void BrickGrid::finish() {
  if (coords_.empty()) {
    cellCount_ = {};
    return;
  }
  BrickCoord lo = coords_[0], hi = coords_[0];
  for (const BrickCoord& c : coords_) {
    lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
    hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
  }
  cellLo_ = lo;
  cellCount_ = {hi.x - lo.x + 1, hi.y - lo.y + 1, hi.z - lo.z + 1};
  cells_.assign(size_t(cellCount_.x) * size_t(cellCount_.y) * size_t(cellCount_.z), -1);
  for (size_t b = 0; b < coords_.size(); ++b) {
    const BrickCoord& c = coords_[b];
    cells_[size_t((int64_t(c.x - lo.x) * cellCount_.y + (c.y - lo.y)) * cellCount_.z + (c.z - lo.z))] = int32_t(b);
  }
  // Trilinear interpolation in a cell reads voxels one beyond it: the neighbours' maxima count.
  majorant_.assign(coords_.size(), 0.0f);
  for (size_t b = 0; b < coords_.size(); ++b) {
    const BrickCoord& c = coords_[b];
    float m = 0;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const int32_t n = brickAt(c.x + dx, c.y + dy, c.z + dz);
          if (n >= 0) m = std::max(m, value_[size_t(n)]);
        }
    majorant_[b] = m;
  }
}

size_t BrickGrid::bytes() const {
  return coords_.capacity() * sizeof(BrickCoord) + kind_.capacity() + index_.capacity() * 4 + value_.capacity() * 4 +
         resident_.capacity() * sizeof(BrickVoxels) + majorant_.capacity() * 4 + cells_.capacity() * 4 +
         (source_ ? size_t(source_->residentBytes()) : 0);
}

}  // namespace rayes
