// The heap's free pages given back to the system (glibc's malloc_trim; no
// effect elsewhere). Memory freed in many small blocks (a triangulation's
// cells) stays resident and is too fragmented for the large arrays that
// follow it; a run's peak resident memory is what the meshers promise.
// Not under AddressSanitizer: its allocator replaces glibc's, whose arenas
// malloc_trim would then set up itself, racily when the labels' threads call
// it at once (a SEGV in mtrim seen in CI's sanitizer run).
#pragma once
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#define IMGMESH_MALLOC_TRIM 1
#include <malloc.h>
#endif

namespace imgmesh {

inline void release_free_memory() {
#if defined(IMGMESH_MALLOC_TRIM)
  malloc_trim(0);
#endif
}

} // namespace imgmesh
