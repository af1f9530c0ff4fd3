// The tetfsi process's allocator set-up (apps/cli/allocator.hpp): after what PETSc's SuperLU_DIST
// does when it is loaded (mallopt(M_MMAP_MAX, 0), mallopt(M_TRIM_THRESHOLD, -1), done here by the
// test itself, whatever this binary links), large blocks are mapped on their own again and given
// back to the system when freed.
#include <gtest/gtest.h>
#include <malloc.h>

#include <cstddef>
#include <cstring>

#include "apps/cli/allocator.hpp"

namespace tetfsi::cli {
namespace {

// GCC defines __SANITIZE_ADDRESS__ under -fsanitize=address; clang answers __has_feature.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

void* volatile keep;  // the block escapes, so the compiler cannot drop its malloc and free

std::size_t mapped_bytes() { return mallinfo2().hblkhd; }

TEST(AllocatorSetUp, LargeBlocksAreMappedAndReturnedWhenFreed) {
  if (kAddressSanitizer)
    GTEST_SKIP() << "AddressSanitizer replaces glibc's allocator: its mallopt and mallinfo2 are not glibc's";
  ASSERT_EQ(mallopt(M_MMAP_MAX, 0), 1);
  ASSERT_EQ(mallopt(M_TRIM_THRESHOLD, -1), 1);
  const std::size_t unmapped = mapped_bytes();
  keep = std::malloc(16u << 20);
  std::memset(keep, 1, 16u << 20);
  EXPECT_EQ(mapped_bytes(), unmapped) << "with M_MMAP_MAX = 0 glibc maps nothing: the case to undo";
  std::free(keep);  // kept in the heap (no trimming)

  ASSERT_TRUE(restore_large_block_mapping());
  constexpr std::size_t kBytes = 64u << 20;  // above the 4 MB threshold and the heap's free 16 MB
  const std::size_t before = mapped_bytes();
  keep = std::malloc(kBytes);
  ASSERT_NE(keep, nullptr);
  std::memset(keep, 1, kBytes);
  EXPECT_GE(mapped_bytes(), before + kBytes) << "a 64 MB block must be a mapping of its own";
  std::free(keep);
  EXPECT_LE(mapped_bytes(), before) << "freeing it must unmap it";
  // A small block stays in the heap.
  keep = std::malloc(1024);
  EXPECT_LE(mapped_bytes(), before);
  std::free(keep);
}

}  // namespace
}  // namespace tetfsi::cli
