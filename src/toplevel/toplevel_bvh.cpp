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

#include "toplevel/toplevel_node.h"

namespace rayes {

using toplevel::Node4;

struct TopLevelBvh::Impl {
  std::vector<Node4> nodes;  // depth first, a parent before its children
  uint32_t root = toplevel::kNoRoot;
  Box3 bounds;
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

// Min-heap order of the traversal: by entry, then by ref (inner nodes before leaves, leaves
// by id; see the kLeafFlag comment in toplevel_node.h).
bool keyLess(const TraversalScratch::Item& a, const TraversalScratch::Item& b) {
  return a.entry < b.entry || (a.entry == b.entry && a.ref < b.ref);
}
bool heapOrder(const TraversalScratch::Item& a, const TraversalScratch::Item& b) {
  return keyLess(b, a);
}

}  // namespace

TopLevelBvh::TopLevelBvh() : impl_(new Impl) {}
TopLevelBvh::~TopLevelBvh() { delete impl_; }

void TopLevelBvh::build(std::span<const Box3> leafBoxes) {
  if (leafBoxes.size() > size_t(toplevel::kMaxLeafId) + 1)
    throw std::length_error("toplevel: too many leaves for 31-bit leaf ids");
  auto impl = std::make_unique<Impl>();

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

    impl->nodes.reserve(prims.size() / 2 + 1);  // ~n/2 inner nodes measured (at most n-1)
    impl->root = flatten(root, leafBoxes, impl->nodes, impl->bounds);
    impl->nodes.shrink_to_fit();
  }  // the Embree tree and device are released here

  delete impl_;
  impl_ = impl.release();
  leafCount_ = leafBoxes.size();
}

int TopLevelBvh::collect(Vec3 org, Vec3 dir, float tmin, float tmax, float resumeEntry,
                         uint32_t resumeLeaf, Candidate* out, int maxCount, float& nextEntry,
                         TraversalScratch& scratch) const {
  using toplevel::isLeafRef;
  using toplevel::refLeafId;
  nextEntry = std::numeric_limits<float>::infinity();
  auto& heap = scratch.heap;
  heap.clear();
  const Impl& m = *impl_;
  if (m.root == toplevel::kNoRoot) return 0;

  // Why the pops come out in (entry, leaf) order: a child's box lies inside its parent's, and
  // the rounded slab distances are monotonic in the plane positions (NaN slabs are ignored on
  // both sides), so a descendant's entry is >= its ancestor's and its exit <=. When a leaf is
  // at the top of the heap, every other item has a larger key; inner items with an equal entry
  // would have a smaller key (their ref orders first), so each remaining inner item has a
  // strictly larger entry and so have all leaves below it. The popped leaf is therefore the
  // next one in (entry, leaf) order, and the heap's minimum entry bounds every leaf not yet
  // returned.
  // Skipping: a leaf at or before the resume point is dropped when found; an inner node whose
  // exit is before resumeEntry holds only such leaves (a leaf's entry <= its exit <= the
  // node's exit), so it is dropped too.
  auto afterResume = [&](float entry, uint32_t leaf) {
    return entry > resumeEntry || (entry == resumeEntry && leaf > resumeLeaf);
  };
  auto keep = [&](uint32_t ref, float entry, float exit) {
    return isLeafRef(ref) ? afterResume(entry, refLeafId(ref)) : exit >= resumeEntry;
  };
  auto push = [&](float entry, uint32_t ref) {
    heap.push_back({entry, ref});
    std::push_heap(heap.begin(), heap.end(), heapOrder);
  };

  const RayBoxQuery q(org, dir);
  float entry, exit;
  if (!intersectBox(q, m.bounds.lo, m.bounds.hi, tmin, tmax, entry, exit)) return 0;
  if (!keep(m.root, entry, exit)) return 0;
  push(entry, m.root);

  int count = 0;
  while (!heap.empty()) {
    const TraversalScratch::Item top = heap.front();
    // Once full, inner nodes are still opened until a leaf is on top, so that nextEntry is the
    // exact entry of the next candidate: a tighter bound terminates more rays, and a needless
    // extra generation (re-dicing a patch) costs far more than these few node visits.
    if (isLeafRef(top.ref) && count >= maxCount) break;
    std::pop_heap(heap.begin(), heap.end(), heapOrder);
    heap.pop_back();
    if (isLeafRef(top.ref)) {
      out[count++] = {refLeafId(top.ref), top.entry};
      continue;
    }
    const Node4& node = m.nodes[top.ref];
    float childEntry[4], childExit[4];
    for (unsigned hit = toplevel::intersectChildren(node, q, tmin, tmax, childEntry, childExit);
         hit != 0; hit &= hit - 1) {
      const int i = std::countr_zero(hit);
      if (keep(node.child[i], childEntry[i], childExit[i])) push(childEntry[i], node.child[i]);
    }
  }
  if (!heap.empty()) nextEntry = heap.front().entry;
  return count;
}

size_t TopLevelBvh::nodeCount() const { return impl_->nodes.size(); }
size_t TopLevelBvh::bytes() const { return impl_->nodes.capacity() * sizeof(Node4); }
Box3 TopLevelBvh::bounds() const { return impl_->bounds; }

namespace toplevel {
std::span<const Node4> Inspector::nodes(const TopLevelBvh& bvh) { return bvh.impl_->nodes; }
uint32_t Inspector::root(const TopLevelBvh& bvh) { return bvh.impl_->root; }
}  // namespace toplevel

}  // namespace rayes
