#include "rays/grid_cache.h"

namespace rayes {

GridCache::Entry* GridCache::acquire(GridKey key, int level) {
  if (!enabled()) return nullptr;
  if (auto found = index_.find(key.packed()); found != index_.end()) {
    auto it = found->second;
    if (it->level >= level) {
      lru_.splice(lru_.begin(), lru_, it);
      it->lastUse = iteration_;
      it->toDice = false;
      ++hits_;
      return &*it;
    }
    erase(it);  // held too coarse: diced again, finer, as a new entry
  }
  const size_t need = DiceBuffer::bytesFor(level);
  if (!makeRoom(need)) return nullptr;
  lru_.push_front(Entry{key, level, nullptr, nullptr, true, iteration_});
  index_[key.packed()] = lru_.begin();
  bytes_ += need;
  if (bytes_ > peakBytes_) peakBytes_ = bytes_;
  return &lru_.front();
}

bool GridCache::makeRoom(size_t need) {
  if (need > budget_) return false;
  while (bytes_ + need > budget_) {
    if (lru_.empty() || lru_.back().lastUse == iteration_) return false;  // the rest is pinned
    erase(std::prev(lru_.end()));
  }
  return true;
}

void GridCache::setBudget(size_t budgetBytes) {
  budget_ = budgetBytes;
  while (bytes_ > budget_ && !lru_.empty()) erase(std::prev(lru_.end()));
}

void GridCache::discard(Entry* entry) {
  if (!entry || !entry->toDice || entry->patch) return;
  if (auto found = index_.find(entry->key.packed()); found != index_.end() && &*found->second == entry) erase(found->second);
}

void GridCache::erase(std::list<Entry>::iterator it) {
  bytes_ -= DiceBuffer::bytesFor(it->level);
  index_.erase(it->key.packed());
  lru_.erase(it);
}

}  // namespace rayes
