// Process CPU time, for the timings a result reports next to wall-clock
// ones: on a shared machine it says more than the wall clock.
#pragma once
#include <ctime>

namespace imgmesh {

inline double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

} // namespace imgmesh
