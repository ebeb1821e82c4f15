#include "forest/core/heap.hpp"

#include <cstdlib>  // defines __GLIBC__ under glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "forest/core/log.hpp"

namespace forest {

void keepFreedHeapMemory() {
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)  // AddressSanitizer's allocator takes no mallopt
  constexpr int kTrimThreshold = 1 << 30;  // bytes free at a heap's top before it is given back
  constexpr int kMmapThreshold = 32 << 20;  // larger blocks come from mmap (and go back when freed)
  if (mallopt(M_TRIM_THRESHOLD, kTrimThreshold) != 1 || mallopt(M_MMAP_THRESHOLD, kMmapThreshold) != 1)
    log::warn("keepFreedHeapMemory: malloc refused the heap thresholds; frames may fault freed pages in again");
#endif
}

}  // namespace forest
