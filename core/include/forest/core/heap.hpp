#pragma once
// The process's heap policy, set once at the start of main(), and its memory in use.

namespace forest {

// Keeps the heap memory that frames free for the next frames instead of handing it back to the
// system. glibc's malloc returns the top of a heap to the kernel once more than its trim threshold
// lies free there (128 KiB, raised only as large blocks are freed), and on a software renderer a
// frame allocates and frees tens of megabytes (llvmpipe's vertex and bin storage for a frame of
// 770 k triangles): every page of it then faulted in again, and zeroed, in the next frame. On a
// virtual machine a page fault is dear. Measured on this project's 2-core VM (`forest bench
// culling --trees 50000 --paths canopy --strategies frustum,chc,chc++ --frames 30`): frustum
// culling's frame 112–168 ms with ~6000 page faults a frame, 48–56 ms with none, the same
// triangles. Here: the trim threshold 1 GiB, and blocks up to 32 MiB (glibc's largest
// threshold) from the heap, not from mmap. A no-op on other C libraries and under AddressSanitizer.
void keepFreedHeapMemory();

// Resident memory of this process, MiB (/proc/self/statm).
double residentMegabytes();

// Heap memory this process holds in blocks not yet freed (malloc's, every thread's arena; under
// AddressSanitizer its allocator's count), MiB. Unlike RSS it falls again when memory is freed.
double heapInUseMegabytes();

}  // namespace forest
