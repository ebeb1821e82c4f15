#include "forest/core/heap.hpp"

#include <unistd.h>

#include <cstddef>
#include <cstdlib>  // defines __GLIBC__ under glibc
#include <fstream>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "forest/core/log.hpp"

#if defined(__SANITIZE_ADDRESS__)
// The sanitizer runtime's count of bytes allocated and not freed (compiler-rt's
// sanitizer/allocator_interface.h, which GCC does not ship).
extern "C" std::size_t __sanitizer_get_current_allocated_bytes();
#endif

namespace forest {

void keepFreedHeapMemory() {
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)  // AddressSanitizer's allocator takes no mallopt
  constexpr int kTrimThreshold = 1 << 30;  // bytes free at a heap's top before it is given back
  constexpr int kMmapThreshold = 32 << 20;  // larger blocks come from mmap (and go back when freed)
  if (mallopt(M_TRIM_THRESHOLD, kTrimThreshold) != 1 || mallopt(M_MMAP_THRESHOLD, kMmapThreshold) != 1)
    log::warn("keepFreedHeapMemory: malloc refused the heap thresholds; frames may fault freed pages in again");
#endif
}

double residentMegabytes() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1 << 20);
}

double heapInUseMegabytes() {
#if defined(__SANITIZE_ADDRESS__)
  const double bytes = static_cast<double>(__sanitizer_get_current_allocated_bytes());  // ASan's allocator replaces glibc's
#else
  const struct mallinfo2 m = mallinfo2();  // every arena: in use from the heaps, plus blocks of their own mmap
  const double bytes = static_cast<double>(m.uordblks) + static_cast<double>(m.hblkhd);
#endif
  return bytes / (1 << 20);
}

}  // namespace forest
