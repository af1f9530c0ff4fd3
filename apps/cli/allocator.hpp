#pragma once
/// @file allocator.hpp
/// The process's memory allocator, set up before anything else runs.
///
/// Debian's libsuperlu_dist, loaded with PETSc, calls mallopt(M_MMAP_MAX, 0) and
/// mallopt(M_TRIM_THRESHOLD, -1) in a load-time constructor: glibc then serves every block from
/// its heaps, however large, and never returns freed memory to the system, so a run's resident
/// memory grows to its heap's peak plus the free space that fragmentation leaves (at 962k fluid
/// tets on the flagship, 16 steps: 275 MB free inside 950 MB of heap). restore_large_block_mapping()
/// maps blocks of 4 MB and more on their own again (unmapped when freed) and trims the heap.
///
/// A block mapped anew is faulted in a page at a time on first touch, which costs (the step's
/// arrays are allocated afresh every step: +0.7 s per step at 962k with 4 kB pages on the test
/// machine). With transparent huge pages in `madvise` mode, glibc's tunable glibc.malloc.hugetlb=1
/// asks for 2 MB pages for its mappings (+0.1 s per step), but glibc reads tunables only when a
/// program starts: use_huge_pages_or_reexec() starts the program again with it set.
namespace tetfsi::cli {

/// If the kernel gives transparent huge pages on request (`madvise` mode) and GLIBC_TUNABLES does
/// not set glibc.malloc.hugetlb, replaces this process by the same program with the same
/// arguments and glibc.malloc.hugetlb=1 added (execv of /proc/self/exe; the process id stays, so
/// mpirun and shells see the same process). Returns only if nothing was to be done or the exec
/// failed (then the run goes on with ordinary pages). Call first thing in main(). A tool that
/// must see one program image from start to end (heaptrack's preload, valgrind) gets it with
/// GLIBC_TUNABLES=glibc.malloc.hugetlb=0 (or =1) set by the caller.
void use_huge_pages_or_reexec(char** argv);

/// The environment part of use_huge_pages_or_reexec: adds glibc.malloc.hugetlb=1 to
/// GLIBC_TUNABLES under the same conditions, for a program this one starts (front.cpp starts
/// tetfsi-solver with it, so that the solver need not start itself again).
/// @return whether GLIBC_TUNABLES was changed
bool request_huge_pages();

/// Maps blocks of at least 4 MB on their own and trims the heaps' free tops above 8 MB (the
/// thresholds fixed: glibc's self-adjusting ones are off once any mallopt call was made).
/// @return false if glibc refused a setting
bool restore_large_block_mapping();

}  // namespace tetfsi::cli
