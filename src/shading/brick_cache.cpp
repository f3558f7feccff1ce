#include "shading/brick_cache.h"
#include <algorithm>
#include <array>
#include <mutex>
#include <stdexcept>
#include <unordered_map>
#include "core/timer.h"

namespace rayes {

struct BrickCache::Slot {
  uint64_t key = ~uint64_t(0);
  uint32_t pins = 0;
  bool referenced = false;
  uint32_t shard = 0;
  std::atomic<uint32_t> apron{kInterior};  // the regions readable (apronRegion bits)
  std::array<float, kSlotVoxels> voxels;
};

struct BrickCache::Shard {
  std::mutex mutex;
  std::vector<std::unique_ptr<Slot>> slots;  // filled lazily up to capacity (stable addresses)
  std::unordered_map<uint64_t, Slot*> byKey;
  size_t hand = 0;  // the CLOCK's hand
  uint64_t hits = 0, loads = 0, evictions = 0;
  double loadSeconds = 0;
};

namespace {

// Pins a thread holds at once: a GridReader holds its brick and one neighbour, and
// volume_tracking.cpp's emissionAlong keeps three readers (density, emission, temperature).
constexpr uint64_t kPinsPerThread = 6;

uint64_t mix(uint64_t k) {  // splitmix64's finaliser: neighbouring bricks land in different shards
  k ^= k >> 30;
  k *= 0xbf58476d1ce4e5b9ull;
  k ^= k >> 27;
  k *= 0x94d049bb133111ebull;
  return k ^ (k >> 31);
}

}  // namespace

uint64_t BrickCache::minimumBytes(int threads) {
  return (kPinsPerThread * uint64_t(std::max(threads, 1)) + 1) * kSlotBytes;
}

BrickCache::BrickCache(uint64_t budgetBytes, int threads, uint64_t totalBricks) : budgetBytes_(budgetBytes) {
  slots_ = budgetBytes / kSlotBytes;
  holdsEverything_ = slots_ >= totalBricks;
  // Every shard must outlast every thread pinning in it at once; beyond that, more shards only
  // lower contention (at most 64: two threads' locks rarely meet there). A quarter of the
  // budget at most is reserved per shard, the rest pooled.
  reserved_ = kPinsPerThread * uint64_t(std::max(threads, 1)) + 1;
  uint64_t shards = 1;
  while (shards < 64 && slots_ >= 8 * shards * reserved_) shards *= 2;
  shards_.resize(size_t(shards));
  for (auto& s : shards_) s = std::make_unique<Shard>();
  pool_ = int64_t(slots_) - int64_t(shards * reserved_);
}

BrickCache::~BrickCache() = default;

const float* BrickCache::acquire(uint32_t grid, uint32_t stored, const BrickSource& source, Slot*& slot) {
  const uint64_t key = uint64_t(grid) << 32 | stored;
  const uint32_t s = uint32_t(mix(key) & (shards_.size() - 1));
  Shard& shard = *shards_[s];
  std::lock_guard lock(shard.mutex);
  if (const auto it = shard.byKey.find(key); it != shard.byKey.end()) {
    slot = it->second;
    ++slot->pins;
    slot->referenced = true;
    ++shard.hits;
    return slot->voxels.data();
  }
  const auto mayGrow = [&] {
    if (holdsEverything_ || shard.slots.size() < reserved_) return true;
    if (pool_.fetch_sub(1, std::memory_order_relaxed) > 0) return true;
    pool_.fetch_add(1, std::memory_order_relaxed);
    return false;
  };
  if (mayGrow()) {
    shard.slots.push_back(std::make_unique<Slot>());
    slot = shard.slots.back().get();
    slot->shard = s;
  } else {
    // CLOCK: skip pinned slots, give referenced ones a second chance. Two sweeps suffice: the
    // first clears every unpinned slot's bit, and fewer slots are pinned than the shard holds.
    for (size_t step = 0;; ++step) {
      if (step > 2 * shard.slots.size() + 1)
        throw std::logic_error("brick cache: every slot of a shard is pinned (budget below minimumBytes)");
      Slot& c = *shard.slots[shard.hand];
      shard.hand = (shard.hand + 1) % shard.slots.size();
      if (c.pins > 0) continue;
      if (c.referenced) {
        c.referenced = false;
        continue;
      }
      slot = &c;
      break;
    }
    shard.byKey.erase(slot->key);
    ++shard.evictions;
  }
  const Clock::time_point t0 = Clock::now();
  std::array<float, kBrickVoxels> brick;
  source.read(stored, brick.data());
  for (int32_t x = 0; x < 8; ++x)
    for (int32_t y = 0; y < 8; ++y)
      std::copy_n(brick.data() + (x * 8 + y) * 8, 8, slot->voxels.data() + paddedIndex(x, y, 0));
  // Relaxed: whoever pins this slot next does so under the shard's lock, which orders it.
  slot->apron.store(kInterior, std::memory_order_relaxed);
  shard.loadSeconds += secondsSince(t0);
  ++shard.loads;
  slot->key = key;
  slot->pins = 1;
  slot->referenced = true;
  shard.byKey.emplace(key, slot);
  return slot->voxels.data();
}

BrickCache::ApronBox BrickCache::apronBox(uint32_t region) {
  ApronBox b{{int32_t(region / 9), int32_t(region / 3 % 3), int32_t(region % 3)}, {}, {}};
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = b.part[a] == 0 ? -1 : b.part[a] == 1 ? 0 : 8;
    b.hi[a] = b.part[a] == 0 ? -1 : b.part[a] == 1 ? 7 : 8;
  }
  return b;
}

uint32_t BrickCache::apronFilled(const Slot* slot) { return slot->apron.load(std::memory_order_acquire); }

void BrickCache::fillApron(Slot* slot, uint32_t region, const float* values) {
  const uint32_t bit = 1u << region;
  Shard& shard = *shards_[slot->shard];
  std::lock_guard lock(shard.mutex);
  if (slot->apron.load(std::memory_order_relaxed) & bit) return;  // another reader filled it
  const ApronBox box = apronBox(region);
  for (int32_t x = box.lo[0]; x <= box.hi[0]; ++x)
    for (int32_t y = box.lo[1]; y <= box.hi[1]; ++y)
      for (int32_t z = box.lo[2]; z <= box.hi[2]; ++z) slot->voxels[size_t(paddedIndex(x, y, z))] = *values++;
  // Release: a reader that sees the bit (apronFilled's acquire) sees the voxels written above.
  slot->apron.fetch_or(bit, std::memory_order_release);
}

void BrickCache::release(Slot* slot) {
  Shard& shard = *shards_[slot->shard];
  std::lock_guard lock(shard.mutex);
  --slot->pins;
}

BrickCacheStats BrickCache::stats() const {
  BrickCacheStats st;
  st.budgetBytes = budgetBytes_;
  st.slots = slots_;
  for (const auto& sp : shards_) {
    Shard& shard = *sp;
    std::lock_guard lock(shard.mutex);
    st.slotsUsed += shard.slots.size();
    st.hits += shard.hits;
    st.loads += shard.loads;
    st.evictions += shard.evictions;
    st.loadSeconds += shard.loadSeconds;
  }
  st.voxelsRead = st.loads * kBrickVoxels;
  st.bytesRead = st.voxelsRead * sizeof(float);
  return st;
}

}  // namespace rayes
