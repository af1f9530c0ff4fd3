// The process's allocator set-up (allocator.hpp).
#include "apps/cli/allocator.hpp"

#include <malloc.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

namespace tetfsi::cli {
namespace {

constexpr const char* kHugePagesTunable = "glibc.malloc.hugetlb=1";
constexpr int kMmapThreshold = 4 << 20;  // the mesh's and solvers' arrays, not node lists and maps

/// True if /sys/kernel/mm/transparent_hugepage/enabled selects `madvise`: huge pages for the
/// mappings a program asks them for (`always` gives them anyway, `never` not at all).
bool huge_pages_on_request() {
  std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  return std::getline(f, modes) && modes.find("[madvise]") != std::string::npos;
}

}  // namespace

bool request_huge_pages() {
#ifdef __GLIBC__
  const char* set = std::getenv("GLIBC_TUNABLES");
  const std::string tunables = set ? set : "";
  if (tunables.find("glibc.malloc.hugetlb") != std::string::npos || !huge_pages_on_request()) return false;
  const std::string with_huge_pages = tunables.empty() ? kHugePagesTunable : tunables + ":" + kHugePagesTunable;
  return setenv("GLIBC_TUNABLES", with_huge_pages.c_str(), 1) == 0;
#else
  return false;
#endif
}

void use_huge_pages_or_reexec(char** argv) {
  const char* set = std::getenv("GLIBC_TUNABLES");
  const std::string before = set ? set : "";
  if (!request_huge_pages()) return;
  execv("/proc/self/exe", argv);  // returns only on failure: go on as we are
  if (set) setenv("GLIBC_TUNABLES", before.c_str(), 1);
  else unsetenv("GLIBC_TUNABLES");
}

bool restore_large_block_mapping() {
#ifdef __GLIBC__
  bool ok = mallopt(M_MMAP_MAX, 65536) == 1;  // glibc's default count of mapped blocks
  ok = mallopt(M_MMAP_THRESHOLD, kMmapThreshold) == 1 && ok;
  ok = mallopt(M_TRIM_THRESHOLD, 2 * kMmapThreshold) == 1 && ok;
  return ok;
#else
  return true;
#endif
}

}  // namespace tetfsi::cli
