// Transparent huge pages for the whole process, by glibc's malloc tunable.
//
// Why: Linux in THP "madvise" mode (Debian's default) backs anonymous memory with 2 MiB pages
// only where madvise(MADV_HUGEPAGE) asked for them. A render allocates hundreds of MiB of ray
// batches, candidates and diced grids; first-touch page faults were 7 % of a small render's perf
// samples, and the tunable below saved 8-22 % of its wall time (bench/history/2026-11.md, "Huge
// pages for the whole process"). glibc (2.35 and later) advises every block its malloc maps when
// GLIBC_TUNABLES holds glibc.malloc.hugetlb=1; tunables are read only at process start, so the
// process starts itself again with the tunable added. Advice only: images never depend on it.
#pragma once

namespace rayes {

// Execs /proc/self/exe with the same arguments and GLIBC_TUNABLES extended by
// glibc.malloc.hugetlb=1, unless the environment already names that tunable, RAYES_HUGE_PAGES
// is "0", or this is not glibc on Linux. Returns only when it did not exec (or the exec failed).
void restartWithHugePages(char** argv);

}  // namespace rayes
