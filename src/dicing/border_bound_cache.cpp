#include "dicing/border_bound_cache.h"
#include <bit>
#include <cstring>

namespace rayes {

BorderBoundCache::BorderBoundCache(size_t capacity) : mask_(std::bit_ceil(std::max<size_t>(capacity, 1)) - 1) {}

// 32 bits of leaf, 2 of kind, 2 of border, 4 of level, 16 of segment; bit 63 marks a valid key.
uint64_t BorderBoundCache::pack(const Key& k) {
  return (uint64_t(1) << 63) | (uint64_t(k.leaf) << 24) | (uint64_t(k.kind) << 22) | (uint64_t(k.border & 3) << 20) |
         (uint64_t(k.level & 15) << 16) | uint64_t(k.segment & 0xffff);
}

namespace {

// splitmix64's finaliser: neighbouring segments and leaves spread over the whole table.
size_t slotOf(uint64_t key, size_t mask) {
  key ^= key >> 30;
  key *= 0xbf58476d1ce4e5b9ull;
  key ^= key >> 27;
  key *= 0x94d049bb133111ebull;
  key ^= key >> 31;
  return size_t(key) & mask;
}

}  // namespace

bool BorderBoundCache::read(uint64_t key, uint32_t (&words)[6]) const {
  if (!allocated_.load(std::memory_order_acquire)) return false;
  const Entry& e = entries_[slotOf(key, mask_)];
  const uint64_t s0 = e.seq.load(std::memory_order_acquire);
  if (s0 & 1) return false;
  if (e.key.load(std::memory_order_relaxed) != key) return false;
  for (int i = 0; i < 6; ++i) words[i] = e.words[i].load(std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_acquire);
  return e.seq.load(std::memory_order_relaxed) == s0;
}

void BorderBoundCache::write(uint64_t key, const uint32_t (&words)[6]) {
  std::call_once(allocate_, [&] {
    entries_ = std::make_unique<Entry[]>(mask_ + 1);
    allocated_.store(true, std::memory_order_release);
  });
  Entry& e = entries_[slotOf(key, mask_)];
  uint64_t s0 = e.seq.load(std::memory_order_relaxed);
  if ((s0 & 1) || !e.seq.compare_exchange_strong(s0, s0 + 1, std::memory_order_acquire)) return;
  std::atomic_thread_fence(std::memory_order_release);  // the odd seq is seen before the new words
  e.key.store(key, std::memory_order_relaxed);
  for (int i = 0; i < 6; ++i) e.words[i].store(words[i], std::memory_order_relaxed);
  e.seq.store(s0 + 2, std::memory_order_release);
}

bool BorderBoundCache::find(const Key& key, Box3& box) const {
  uint32_t w[6];
  if (!read(pack(key), w)) return false;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = std::bit_cast<float>(w[a]);
    box.hi[a] = std::bit_cast<float>(w[3 + a]);
  }
  return true;
}

bool BorderBoundCache::find(const Key& key, double& radius) const {
  uint32_t w[6];
  if (!read(pack(key), w)) return false;
  radius = std::bit_cast<double>(uint64_t(w[0]) | (uint64_t(w[1]) << 32));
  return true;
}

void BorderBoundCache::insert(const Key& key, const Box3& box) {
  uint32_t w[6];
  for (int a = 0; a < 3; ++a) {
    w[a] = std::bit_cast<uint32_t>(box.lo[a]);
    w[3 + a] = std::bit_cast<uint32_t>(box.hi[a]);
  }
  write(pack(key), w);
}

void BorderBoundCache::insert(const Key& key, double radius) {
  const uint64_t bits = std::bit_cast<uint64_t>(radius);
  const uint32_t w[6] = {uint32_t(bits), uint32_t(bits >> 32), 0, 0, 0, 0};
  write(pack(key), w);
}

}  // namespace rayes
