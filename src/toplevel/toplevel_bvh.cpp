// TopLevelBvh: Embree builds the tree (binned SAH, 4-wide, one box per leaf) through the
// rtcBuildBVH callbacks into a temporary pointer tree in Embree's memory; we then flatten it
// into a depth-first std::vector<Node4> and release everything Embree allocated.
#include "toplevel/toplevel_bvh.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "toplevel/toplevel_node.h"

namespace rayes {

using toplevel::Node4;

// Built: the nodes and boxes are owned, and the spans read them ungated. Adopted: the owned
// vectors stay empty and the spans read the stored tree through its gates.
struct TopLevelBvh::Impl {
  std::vector<Node4> ownedNodes;  // depth first, a parent before its children
  std::vector<Box3> ownedBoxes;   // what it was built over, by leaf id
  GatedSpan<Node4> nodes;
  GatedSpan<Box3> leafBoxes;
  uint32_t root = toplevel::kNoRoot;
  Box3 bounds;
  bool adopted = false;
};

namespace {

// Embree's side of the build: nodes live in the RTCBVH's thread-local arenas and die with it.
struct BuildItem {
  bool leaf;
};
struct BuildLeaf : BuildItem {
  uint32_t id;
};
struct BuildInner : BuildItem {
  unsigned count;
  const BuildItem* child[4];
};

struct BuildContext {
  std::atomic<bool> multiPrimLeaf{false};  // cannot throw through Embree; checked afterwards
};

void* createNode(RTCThreadLocalAllocator alloc, unsigned int childCount, void*) {
  void* mem = rtcThreadLocalAlloc(alloc, sizeof(BuildInner), alignof(BuildInner));
  auto* node = new (mem) BuildInner;
  node->leaf = false;
  node->count = childCount;
  return node;
}

void setNodeChildren(void* nodePtr, void** children, unsigned int childCount, void*) {
  auto* node = static_cast<BuildInner*>(nodePtr);
  node->count = childCount;
  for (unsigned i = 0; i < childCount; ++i) node->child[i] = static_cast<const BuildItem*>(children[i]);
}

// Child bounds are recomputed from the input boxes while flattening (min/max only, so exact):
// the containment of every leaf box in its ancestors' boxes then holds by construction,
// whatever Embree does with the bounds internally.
void setNodeBounds(void*, const RTCBounds**, unsigned int, void*) {}

void* createLeaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count,
                 void* userPtr) {
  if (count != 1) static_cast<BuildContext*>(userPtr)->multiPrimLeaf = true;
  void* mem = rtcThreadLocalAlloc(alloc, sizeof(BuildLeaf), alignof(BuildLeaf));
  auto* leaf = new (mem) BuildLeaf;
  leaf->leaf = true;
  leaf->id = prims[0].primID;
  return leaf;
}

struct DeviceDeleter { void operator()(RTCDevice d) const { rtcReleaseDevice(d); } };
struct BvhDeleter { void operator()(RTCBVH b) const { rtcReleaseBVH(b); } };
using DevicePtr = std::unique_ptr<RTCDeviceTy, DeviceDeleter>;
using BvhPtr = std::unique_ptr<RTCBVHTy, BvhDeleter>;

[[noreturn]] void embreeFailure(RTCDevice device, const char* what) {
  const int code = device ? int(rtcGetDeviceError(device)) : -1;
  throw std::runtime_error(std::string("toplevel: ") + what + " (Embree error " +
                           std::to_string(code) + ")");
}

// Appends the subtree of `item` to `nodes` depth first; returns its ref and sets its box.
uint32_t flatten(const BuildItem* item, std::span<const Box3> boxes, std::vector<Node4>& nodes,
                 Box3& box) {
  if (item->leaf) {
    const uint32_t id = static_cast<const BuildLeaf*>(item)->id;
    box = boxes[id];
    return toplevel::leafRef(id);
  }
  const auto* inner = static_cast<const BuildInner*>(item);
  const auto index = static_cast<uint32_t>(nodes.size());
  nodes.emplace_back();
  Node4 node;
  node.count = inner->count;
  box = Box3{};
  for (int i = 0; i < 4; ++i) {
    Box3 childBox;  // default: inverted, the empty-slot marker
    node.child[i] = toplevel::kEmptyRef;
    if (i < int(inner->count)) node.child[i] = flatten(inner->child[i], boxes, nodes, childBox);
    for (int a = 0; a < 3; ++a) {
      node.lo[a][i] = childBox.lo[a];
      node.hi[a][i] = childBox.hi[a];
    }
    box.extend(childBox);
  }
  nodes[index] = node;  // assigned last: the recursion may have reallocated `nodes`
  return index;
}

constexpr bool candidateLess(const Candidate& a, const Candidate& b) {
  return a.entry < b.entry || (a.entry == b.entry && a.leaf < b.leaf);
}

// The best maxCount + 1 candidates found so far, sorted: the first maxCount live in the
// caller's buffer, the one after them (which becomes nextEntry) in `extra`. Leaves arrive
// roughly front to back, so insertion from the end rarely moves anything.
class BestList {
 public:
  BestList(Candidate* out, int maxCount) : out_(out), maxCount_(std::max(maxCount, 0)) {}
  bool full() const { return size_ > maxCount_; }
  const Candidate& last() const { return at(size_ - 1); }
  // Only called with c before last() when full.
  void insert(const Candidate& c) {
    int pos = size_;
    while (pos > 0 && candidateLess(c, at(pos - 1))) --pos;
    size_ = std::min(size_ + 1, maxCount_ + 1);
    for (int i = size_ - 1; i > pos; --i) at(i) = at(i - 1);
    at(pos) = c;
  }
  int returned() const { return std::min(size_, maxCount_); }
  float nextEntry() const { return full() ? extra_.entry : std::numeric_limits<float>::infinity(); }

 private:
  Candidate& at(int i) { return i < maxCount_ ? out_[i] : extra_; }
  const Candidate& at(int i) const { return i < maxCount_ ? out_[i] : extra_; }
  Candidate* out_;
  int maxCount_;
  int size_ = 0;
  Candidate extra_{};
};

}  // namespace

TopLevelBvh::TopLevelBvh() : impl_(new Impl) {}
TopLevelBvh::~TopLevelBvh() { delete impl_; }

void TopLevelBvh::build(std::span<const Box3> leafBoxes) { build(std::vector<Box3>(leafBoxes.begin(), leafBoxes.end())); }

void TopLevelBvh::build(std::vector<Box3>&& boxes) {
  if (boxes.size() > size_t(toplevel::kMaxLeafId) + 1)
    throw std::length_error("toplevel: too many leaves for 31-bit leaf ids");
  auto impl = std::make_unique<Impl>();
  impl->ownedBoxes = std::move(boxes);
  const std::span<const Box3> leafBoxes = impl->ownedBoxes;

  std::vector<RTCBuildPrimitive> prims;
  prims.reserve(leafBoxes.size());
  for (size_t i = 0; i < leafBoxes.size(); ++i) {
    const Box3& b = leafBoxes[i];
    if (b.empty()) continue;
    prims.push_back({b.lo.x, b.lo.y, b.lo.z, 0u, b.hi.x, b.hi.y, b.hi.z, uint32_t(i)});
  }

  if (!prims.empty()) {
    DevicePtr device(rtcNewDevice(nullptr));
    if (!device) embreeFailure(nullptr, "rtcNewDevice failed");
    BvhPtr bvh(rtcNewBVH(device.get()));
    if (!bvh) embreeFailure(device.get(), "rtcNewBVH failed");

    BuildContext context;
    RTCBuildArguments args = rtcDefaultBuildArguments();
    args.buildQuality = RTC_BUILD_QUALITY_MEDIUM;  // binned SAH
    args.maxBranchingFactor = 4;
    args.minLeafSize = 1;  // one patch per leaf: the leaf id is the patch id
    args.maxLeafSize = 1;
    args.bvh = bvh.get();
    args.primitives = prims.data();
    args.primitiveCount = prims.size();
    args.primitiveArrayCapacity = prims.size();  // no spatial splits at MEDIUM quality
    args.createNode = createNode;
    args.setNodeChildren = setNodeChildren;
    args.setNodeBounds = setNodeBounds;
    args.createLeaf = createLeaf;
    args.userPtr = &context;
    const auto* root = static_cast<const BuildItem*>(rtcBuildBVH(&args));
    if (!root) embreeFailure(device.get(), "rtcBuildBVH failed");
    if (context.multiPrimLeaf) throw std::logic_error("toplevel: Embree made a leaf of several boxes");
    // The primitives are Embree's input only: released before the nodes are made, so that the
    // two never take memory at once (32 + 64 bytes per leaf).
    std::vector<RTCBuildPrimitive>().swap(prims);

    impl->ownedNodes.reserve(leafBoxes.size() / 2 + 1);  // ~n/2 inner nodes measured (at most n-1)
    impl->root = flatten(root, leafBoxes, impl->ownedNodes, impl->bounds);
    impl->ownedNodes.shrink_to_fit();
  }  // the Embree tree and device are released here
  impl->nodes = GatedSpan<Node4>(impl->ownedNodes.data(), impl->ownedNodes.size());
  impl->leafBoxes = GatedSpan<Box3>(impl->ownedBoxes.data(), impl->ownedBoxes.size());

  delete impl_;
  impl_ = impl.release();
  leafCount_ = leafBoxes.size();
}

int TopLevelBvh::collect(Vec3 org, Vec3 dir, float tmin, float tmax, float resumeEntry,
                         uint32_t resumeLeaf, Candidate* out, int maxCount, float& nextEntry,
                         TraversalScratch& scratch, uint32_t* nextLeaf) const {
  using toplevel::isLeafRef;
  using toplevel::refLeafId;
  // Depth first, nearest child first, keeping the best maxCount + 1 leaves after the resume
  // point (a k-nearest search along the ray); the (maxCount + 1)-th gives the exact nextEntry.
  // Why nothing is missed: a child's box lies inside its parent's, and the rounded slab
  // distances are monotonic in the plane positions (NaN slabs are ignored on both sides), so
  // a leaf the ray crosses is crossed by all its ancestors, each with entry <= the leaf's entry
  // and exit >= the leaf's exit >= its entry. Hence a node is dropped safely when
  //  - its entry is beyond the (maxCount + 1)-th best leaf found so far: every leaf below it
  //    would come later (equal entries are kept: a smaller leaf id may lie below), or
  //  - its exit is before resumeEntry: every leaf below it was returned by an earlier call.
  // (A best-first heap keyed by (entry, ref) was measured too: about as many node visits,
  // equal speed at N = 8 and about 1.3x slower at N = 1, so the simpler stack stays.)
  nextEntry = std::numeric_limits<float>::infinity();
  const Impl& m = *impl_;
  if (m.root == toplevel::kNoRoot) return 0;
  BestList best(out, maxCount);
  auto offerLeaf = [&](uint32_t ref, float entry) {
    const Candidate c{refLeafId(ref), entry};
    const bool afterResume = entry > resumeEntry || (entry == resumeEntry && c.leaf > resumeLeaf);
    if (afterResume && (!best.full() || candidateLess(c, best.last()))) best.insert(c);
  };
  auto nodeWanted = [&](float entry, float exit) {
    return exit >= resumeEntry && (!best.full() || entry <= best.last().entry);
  };

  const RayBoxQuery q(org, dir);
  const RayBox4Query q4(q);
  float entry, exit;
  if (!intersectBox(q, m.bounds.lo, m.bounds.hi, tmin, tmax, entry, exit)) return 0;
  if (isLeafRef(m.root)) {
    offerLeaf(m.root, entry);
  } else if (nodeWanted(entry, exit)) {
    auto& stack = scratch.heap;
    stack.clear();
    stack.push_back({entry, m.root});
    while (!stack.empty()) {
      const TraversalScratch::Item item = stack.back();
      stack.pop_back();
      if (best.full() && item.entry > best.last().entry) continue;  // the bound has tightened
      const Node4& node = m.nodes.at(item.ref);
      float childEntry[4], childExit[4];
      unsigned hit = toplevel::intersectChildren(node, q4, tmin, tmax, childEntry, childExit);
      // Inner children go on the stack farthest first, so the nearest is visited next.
      TraversalScratch::Item inner[4];
      int innerCount = 0;
      for (; hit != 0; hit &= hit - 1) {
        const int i = std::countr_zero(hit);
        const uint32_t ref = node.child[i];
        if (isLeafRef(ref)) {
          offerLeaf(ref, childEntry[i]);
        } else if (nodeWanted(childEntry[i], childExit[i])) {
          int pos = innerCount++;
          for (; pos > 0 && inner[pos - 1].entry < childEntry[i]; --pos) inner[pos] = inner[pos - 1];
          inner[pos] = {childEntry[i], ref};
        }
      }
      for (int i = 0; i < innerCount; ++i) {
        // Fetched now, used a few iterations later: hides part of the cache miss.
        __builtin_prefetch(&m.nodes.data()[inner[i].ref].lo);
        __builtin_prefetch(&m.nodes.data()[inner[i].ref].hi[1]);
        stack.push_back(inner[i]);
      }
    }
  }
  nextEntry = best.nextEntry();
  if (nextLeaf && best.full()) *nextLeaf = best.last().leaf;
  return best.returned();
}

bool TopLevelBvh::anyOtherLeafMeets(const Box3& box, uint32_t except) const {
  using toplevel::isLeafRef;
  using toplevel::refLeafId;
  const Impl& m = *impl_;
  if (m.root == toplevel::kNoRoot || box.empty()) return false;
  const auto meets = [&](const Vec3& lo, const Vec3& hi) {
    return lo.x <= box.hi.x && lo.y <= box.hi.y && lo.z <= box.hi.z && hi.x >= box.lo.x && hi.y >= box.lo.y &&
           hi.z >= box.lo.z;
  };
  if (!meets(m.bounds.lo, m.bounds.hi)) return false;
  if (isLeafRef(m.root)) return refLeafId(m.root) != except;
  std::vector<uint32_t> stack{m.root};
  while (!stack.empty()) {
    const Node4& node = m.nodes.at(stack.back());
    stack.pop_back();
    for (int i = 0; i < 4; ++i) {
      const uint32_t ref = node.child[i];
      // Unused slots hold inverted boxes, which meet nothing.
      if (!meets({node.lo[0][i], node.lo[1][i], node.lo[2][i]}, {node.hi[0][i], node.hi[1][i], node.hi[2][i]}))
        continue;
      if (!isLeafRef(ref)) stack.push_back(ref);
      else if (refLeafId(ref) != except) return true;
    }
  }
  return false;
}

size_t TopLevelBvh::nodeCount() const { return impl_->nodes.size(); }
size_t TopLevelBvh::bytes() const {
  return impl_->ownedNodes.capacity() * sizeof(Node4) + impl_->ownedBoxes.capacity() * sizeof(Box3);
}
GatedSpan<Box3> TopLevelBvh::leafBoxes() const { return impl_->leafBoxes; }
Box3 TopLevelBvh::bounds() const { return impl_->bounds; }
bool TopLevelBvh::adopted() const { return impl_->adopted; }

TopLevelBvh::Stored TopLevelBvh::stored() const {
  static_assert(sizeof(Node4) == kNodeBytes);
  return {impl_->nodes.data(), impl_->nodes.size(), impl_->root};
}

void TopLevelBvh::adopt(const void* nodeBytes, size_t nodeCount, const BlockGate* nodeGate, uint64_t nodeOffset,
                        uint32_t root, GatedSpan<Box3> leafBoxes) {
  using toplevel::isLeafRef;
  using toplevel::refLeafId;
  if (leafBoxes.size() > size_t(toplevel::kMaxLeafId) + 1 || nodeCount >= toplevel::kLeafFlag)
    throw std::invalid_argument("more leaves or nodes than refs can name");
  if (reinterpret_cast<uintptr_t>(nodeBytes) % alignof(Node4) != 0) throw std::invalid_argument("the nodes are not aligned");
  auto impl = std::make_unique<Impl>();
  impl->adopted = true;
  impl->nodes = GatedSpan<Node4>(static_cast<const Node4*>(nodeBytes), nodeCount, nodeGate, nodeOffset);
  impl->leafBoxes = leafBoxes;
  impl->root = root;
  const size_t leaves = leafBoxes.size();
  const auto leafOk = [&](uint32_t ref) { return isLeafRef(ref) && ref != toplevel::kEmptyRef && refLeafId(ref) < leaves; };
  if (nodeCount == 0 ? root != toplevel::kNoRoot && !leafOk(root) : root != 0)
    throw std::invalid_argument("root ref " + std::to_string(root) + " with " + std::to_string(nodeCount) + " nodes");
  // Depth first: every inner child lies after its parent, so refs in range and increasing
  // make a tree the traversal walks in bounded time; unused slots must be rejected by every
  // ray (inverted boxes) and name no leaf.
  const GatedSpan<Node4>& nodes = impl->nodes;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, nodeCount, 512), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) {
      const Node4& n = nodes.at(k);
      bool ok = n.count >= 1 && n.count <= 4;
      for (unsigned i = 0; ok && i < 4; ++i) {
        const uint32_t ref = n.child[i];
        if (i < n.count) {
          ok = isLeafRef(ref) ? leafOk(ref) : ref > k && ref < nodeCount;
        } else {
          ok = ref == toplevel::kEmptyRef;
          for (int a = 0; a < 3; ++a)
            ok = ok && n.lo[a][i] == std::numeric_limits<float>::infinity() && n.hi[a][i] == -std::numeric_limits<float>::infinity();
        }
      }
      if (!ok) throw std::invalid_argument("node " + std::to_string(k) + " has an impossible child or count");
    }
  });
  // The scene's bounds as flatten() made them: the union of the root's four slots.
  if (isLeafRef(root)) {
    if (root != toplevel::kNoRoot) impl->bounds = leafBoxes[refLeafId(root)];
  } else {
    const Node4& n = nodes.at(0);
    for (int i = 0; i < 4; ++i)
      impl->bounds.extend(Box3{{n.lo[0][i], n.lo[1][i], n.lo[2][i]}, {n.hi[0][i], n.hi[1][i], n.hi[2][i]}});
  }
  delete impl_;
  impl_ = impl.release();
  leafCount_ = leaves;
}

void TopLevelBvh::overlapping(const Box3& box, std::vector<uint32_t>& out, TraversalScratch& scratch) const {
  using toplevel::isLeafRef;
  const Impl& m = *impl_;
  const size_t first = out.size();
  if (m.root == toplevel::kNoRoot || box.empty()) return;
  auto overlaps = [&](const Box3& b) {
    return b.lo.x <= box.hi.x && b.hi.x >= box.lo.x && b.lo.y <= box.hi.y && b.hi.y >= box.lo.y &&
           b.lo.z <= box.hi.z && b.hi.z >= box.lo.z;
  };
  if (!overlaps(m.bounds)) return;
  if (isLeafRef(m.root)) {
    out.push_back(toplevel::refLeafId(m.root));
    return;
  }
  auto& stack = scratch.heap;
  stack.clear();
  stack.push_back({0.0f, m.root});
  while (!stack.empty()) {
    const uint32_t ref = stack.back().ref;
    stack.pop_back();
    const toplevel::Node4& node = m.nodes.at(ref);
    for (int c = 0; c < 4; ++c) {
      if (node.child[c] == toplevel::kEmptyRef) continue;
      const Box3 child{{node.lo[0][c], node.lo[1][c], node.lo[2][c]}, {node.hi[0][c], node.hi[1][c], node.hi[2][c]}};
      if (!overlaps(child)) continue;
      if (isLeafRef(node.child[c])) out.push_back(toplevel::refLeafId(node.child[c]));
      else stack.push_back({0.0f, node.child[c]});
    }
  }
  std::sort(out.begin() + first, out.end());
}

namespace toplevel {
std::span<const Node4> Inspector::nodes(const TopLevelBvh& bvh) { return {bvh.impl_->nodes.data(), bvh.impl_->nodes.size()}; }
uint32_t Inspector::root(const TopLevelBvh& bvh) { return bvh.impl_->root; }
}  // namespace toplevel

}  // namespace rayes
