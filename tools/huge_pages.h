#pragma once
// Transparent huge pages for the heap of Quiver's executables (docs/performance.md).

namespace quiver::tools {

/// Sets GLIBC_TUNABLES=glibc.malloc.hugetlb=1 for the programs this one starts: glibc's malloc
/// then asks the kernel for transparent huge pages for its heap (Debian's kernels serve them in
/// their default "madvise" mode). With `here`, also re-executes this program (same arguments,
/// same process) to run with it: for a process that holds a replica. A replica takes its memory
/// in many small pieces, and the first touch of each 4 KiB page is a page fault: a late joiner
/// of a 10k-node world took 1.6 times as long without (docs/performance.md). Does nothing when
/// GLIBC_TUNABLES already names glibc.malloc.hugetlb (the re-executed program, or a user's own
/// choice) or QUIVER_HUGE_PAGES=0. Call it first in main(): nothing before it survives the exec.
void use_huge_pages(char** argv, bool here);

}  // namespace quiver::tools
