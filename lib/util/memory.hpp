// The heap's free pages given back to the system (glibc's malloc_trim; no
// effect elsewhere). Memory freed in many small blocks (a triangulation's
// cells) stays resident and is too fragmented for the large arrays that
// follow it; a run's peak resident memory is what the meshers promise.
#pragma once
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace imgmesh {

inline void release_free_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

} // namespace imgmesh
