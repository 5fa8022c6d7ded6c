// A vector of zeros that costs only the pages later written: its memory
// comes from calloc (large blocks: the kernel's zero pages, untouched until
// written) and sizing it (vector(n), resize(n) on a fresh vector) writes no
// element. For tables over a whole scan of which a small label writes a few
// pages (CubeGrid's bit sets; SampleGrid's block table, its box's): a memset of all of
// them cost a label of 13 voxels of a 512x512x400 scan most of its time.
#pragma once
#include <cstddef>
#include <cstdlib>
#include <new>
#include <utility>
#include <vector>

namespace imgmesh {

template <class T> struct ZeroedAllocator {
  using value_type = T;
  ZeroedAllocator() = default;
  template <class U> ZeroedAllocator(const ZeroedAllocator<U>&) {}
  T* allocate(std::size_t n) {
    void* p = std::calloc(n, sizeof(T));
    if (!p) throw std::bad_alloc();
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t) { std::free(p); }
  // Default-initialised, not zeroed again (T trivial: calloc's zeros stay).
  template <class U> void construct(U* p) { ::new (static_cast<void*>(p)) U; }
  template <class U, class... A> void construct(U* p, A&&... a) { ::new (static_cast<void*>(p)) U(std::forward<A>(a)...); }
  template <class U> bool operator==(const ZeroedAllocator<U>&) const { return true; }
  template <class U> bool operator!=(const ZeroedAllocator<U>&) const { return false; }
};

// n zeros; T trivial. Only grown from empty by resize (memory reused after a
// clear() would keep its old values).
template <class T> using ZeroedVector = std::vector<T, ZeroedAllocator<T>>;

} // namespace imgmesh
