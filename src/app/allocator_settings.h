// How the process's allocator returns memory (glibc on Linux; a no-op elsewhere).
//
// Why: every budget the renderer keeps (--ray-memory, --grid-cache, --beam-memory) counts what it
// holds; the resident set should follow those counts. glibc serves blocks above its mmap
// threshold from mmap and unmaps them when freed, but the first free of such a block raises the
// threshold to that block's size, so later blocks of that size (diced grids, beam ranges) come
// from the heap and stay resident after they are freed. On two quads at --beam-resolution 1024
// with --beam-memory 256M that kept the peak resident set 24 MB above the non-beam memory plus
// the budget; with the threshold fixed at 1 MiB it is within it: 249-254 MB against 12 + 268
// (bench/history/2026-11.md, "Beams within their memory: the resident set"). A teapot render was
// not slower: 6.30 s of CPU against 6.80 s, three alternating runs each.
#pragma once

namespace rayes {

// Fixes glibc's mmap threshold at 1 MiB (mallopt M_MMAP_THRESHOLD), which also turns its dynamic
// raising off (at 128 KiB, its initial value, the teapot took about 5 % more CPU). Call once,
// first thing in main.
void returnLargeBlocksWhenFreed();

}  // namespace rayes
