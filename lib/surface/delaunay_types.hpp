// The triangulation the mesher works on (private to lib/surface): CGAL's
// Delaunay_triangulation_3 whose vertices know their id, origin and S
// component, and whose cells keep EdgeSurface's answer for each facet.
// Included only by the .cpp files of the rooms that need CGAL.
#pragma once
#include "surface/vec3.hpp"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Robust_weighted_circumcenter_filtered_traits_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <stdexcept>
#include <utility>
#include <vector>

namespace imgmesh::surface_detail {

using K0 = CGAL::Exact_predicates_inexact_constructions_kernel;
// Circumcentres in floating point, checked with an exact predicate to lie
// inside the tetrahedron's circumsphere, else computed exactly and rounded
// (Mesh_3's traits; Surface_mesher's always go through the lazy exact kernel).
using GT = CGAL::Robust_circumcenter_filtered_traits_3<K0>;
using Point = GT::Point_3;

// Why a vertex is in W; also the per-subroutine counters of --stats.
// kVolume: implicit2tet's cell circumcentres (lib/volume), not on S;
// kBox: its points on the box of --outside (corners and box splits).
// kVoxelSide: VoxelSides' points (issue 38), on S.
enum Origin : std::uint8_t { kSeed, kVorEdge, kTopoDisk, kFacetCycle, kHandle, kQuality, kSmooth, kDistance, kFallback, kVoxelSide, kVolume, kBox, kOrigins };
inline constexpr const char* kOriginName[kOrigins] = {"seed", "vor_edge", "topo_disk", "facet_cycle", "handle_detection", "quality", "smooth", "max_distance", "topology_fallback", "voxel_side", "volume", "box"};
// A vertex placed on S (by the surface mesher), not by implicit2tet off S.
inline bool on_surface(std::uint8_t origin) { return origin < kVolume; }

struct VInfo {  // 16 bytes: the three bytes last (a vertex of 56 bytes, not 64)
  int id = -1;
  int comp = -1;  // S component (active-cube component) the vertex lies on
  std::uint32_t stamp = 0;  // last insertion that collected this vertex
  std::uint8_t origin = kSeed;
  std::uint8_t queued = 0;  // 1: TopoDisk check queued, 2: SMOOTH check queued; DelMesh: 4, 8, 16
  std::uint8_t listed = 0;  // star_vertices' mark while it lists a star (star.hpp)
};

enum : std::uint8_t { kComputed = 1, kRestricted = 2, kMulti = 4 };

// EdgeSurface's answer for one Delaunay facet.
struct FacetInfo {
  double x[3] = {0, 0, 0};  // surface centre x_t: crossing farthest from the facet's vertices
  double r2 = 0;            // squared radius of the surface Delaunay ball
  float grad[3] = {0, 0, 0};  // grad f at x_t (orients the facet for SMOOTH and output)
  std::uint32_t computed = 0;  // which computation: queue entries of older ones are stale
  std::uint8_t state = 0;
};

// The records of restricted facets, one per facet shared by its two sides,
// numbered by 30 bits (a cell holds 4 numbers in 15 bytes, not 4 pointers)
// and kept in chunks that never move, so threads read them while others
// allocate; 0 and 1 are the constant records "not computed" and "computed,
// not restricted". Shared by every mesh of the process (seg2mesh meshes
// labels on several threads at once): allocation under a mutex.
class FacetPool {
public:
  static constexpr std::uint32_t kUncomputed = 0, kComputedOnly = 1;
  static constexpr int kBits = 30;  // a record's number (FacetRefs packs four)
  static constexpr std::uint32_t kLimit = 1u << kBits;
  static const FacetInfo& get(std::uint32_t i) { return table_[i >> kShift][i & kMask]; }
  // A record for fi, held by two sides.
  static std::uint32_t make(const FacetInfo& fi) {
    std::lock_guard<std::mutex> lock(mutex());
    State& st = state();
    std::uint32_t i = st.free;
    if (i != kNone) {
      st.free = table_[i >> kShift][i & kMask].link;
    } else {
      if (st.used == kLimit) throw std::length_error("FacetPool: 2^30 facet records");
      if ((st.used & kMask) == 0) table_[st.used >> kShift] = new Shared[kMask + 1];
      i = st.used++;
    }
    Shared& r = table_[i >> kShift][i & kMask];
    static_cast<FacetInfo&>(r) = fi;
    r.link = 2;
    return i;
  }
  // One side lets go of record i (a constant one is never freed).
  static void release(std::uint32_t i) {
    if (i <= kComputedOnly) return;
    Shared& r = table_[i >> kShift][i & kMask];
    if (--r.link > 0) return;
    std::lock_guard<std::mutex> lock(mutex());
    State& st = state();
    r.link = st.free;
    st.free = i;
  }

private:
  // Chunks of 4096 records (229 KB): the last one, constructed whole, is
  // mostly unused at the run's peaks (chunks of 16384 held up to 0.9 MB
  // more; the chunk table is zero pages but for the chunks made).
  static constexpr int kShift = 12;
  static constexpr std::uint32_t kMask = (1u << kShift) - 1, kChunks = 1u << (kBits - kShift), kNone = 0xffffffffu;
  static_assert(sizeof(FacetInfo) == 56, "FacetInfo: 49 bytes of fields");
  // The link sits in FacetInfo's tail padding (56 bytes a record): the
  // sides holding the record, or when free the next free one.
  struct Shared : FacetInfo {
    std::uint32_t link = 0;
  };
  struct State {
    std::uint32_t used = 2;  // records handed out so far (0, 1: the constants)
    std::uint32_t free = kNone;
  };
  // The chunk table, zero pages until used (calloc of a large block).
  static Shared** make_table() {
    auto** t = static_cast<Shared**>(std::calloc(kChunks, sizeof(Shared*)));
    if (!t) throw std::bad_alloc();
    t[0] = new Shared[kMask + 1];
    t[0][kComputedOnly].state = kComputed;
    return t;
  }
  static inline Shared** const table_ = make_table();
  static State& state() {
    static State s;
    return s;
  }
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
};

// A cell's four facets, each the number of its FacetPool record, shared by
// the facet's two sides; only restricted facets (a few in ten) have a
// record of their own. Only DELMESH sets them; a copied cell starts with
// its facets not computed. The four 30-bit numbers are packed in 15 bytes
// of alignment 1, which the compiler places in the tail padding of CGAL's
// cell base (65 bytes used of 72): the cell is 80 bytes, where four
// 32-bit numbers made it 88 (cells are most of the run's memory).
class FacetRefs {
public:
  FacetRefs() {  // all kUncomputed (0): two 8-byte stores, not a call to memset
    const std::uint64_t zero = 0;
    std::memcpy(b_, &zero, 8);
    std::memcpy(b_ + 7, &zero, 8);
  }
  FacetRefs(const FacetRefs&) : FacetRefs() {}
  FacetRefs& operator=(const FacetRefs&) {
    for (int i = 0; i < 4; ++i) clear(i);
    return *this;
  }
  ~FacetRefs() {
    for (int i = 0; i < 4; ++i) FacetPool::release(ref(i));
  }
  const FacetInfo& operator[](int i) const { return FacetPool::get(ref(i)); }
  // The state from the number alone (no record read): 0 is "not computed",
  // 1 "computed, not restricted", and only restricted facets have records
  // of their own (kMulti comes with kRestricted).
  bool computed(int i) const { return ref(i) != FacetPool::kUncomputed; }
  bool restricted(int i) const { return ref(i) > FacetPool::kComputedOnly; }
  // Facet i of `a`, which is facet j of `b`, is now fi (on both sides).
  static void set(FacetRefs& a, int i, FacetRefs& b, int j, const FacetInfo& fi) {
    FacetPool::release(a.ref(i));
    FacetPool::release(b.ref(j));
    const std::uint32_t r = fi.state == kComputed ? FacetPool::kComputedOnly : FacetPool::make(fi);
    a.put(i, r);
    b.put(j, r);
  }
  void clear(int i) {
    FacetPool::release(ref(i));
    put(i, FacetPool::kUncomputed);
  }
  // Number i (bits 30 i .. 30 i + 29), read from the 8 bytes at 0 (i < 2)
  // or at 7 (i >= 2), which hold it whole.
  std::uint32_t ref(int i) const {
    std::uint64_t w;
    std::memcpy(&w, b_ + at(i), 8);
    return std::uint32_t(w >> shift(i)) & kMask;
  }
  void put(int i, std::uint32_t r) {
    std::uint64_t w;
    std::memcpy(&w, b_ + at(i), 8);
    w = (w & ~(std::uint64_t(kMask) << shift(i))) | std::uint64_t(r) << shift(i);
    std::memcpy(b_ + at(i), &w, 8);
  }

private:
  static constexpr std::uint32_t kMask = FacetPool::kLimit - 1;
  static int at(int i) { return (i >> 1) * 7; }                // 0, 0, 7, 7
  static int shift(int i) { return (i & 1) * 30 + (i >> 1) * 4; }  // 30 i - 8 at(i): 0, 30, 4, 34
  static_assert(FacetPool::kBits == 30, "at() and shift() place four 30-bit numbers");
  std::uint8_t b_[(4 * FacetPool::kBits + 7) / 8];  // 15
};

// The circumcentre from the vertices in lexicographic order. From CGAL's
// vertex order, which vertex removal makes depend on addresses, it would
// differ in its last bits from run to run. Computed on each call, not kept
// in the cell (24 of the cell's bytes): about 500 instructions since the
// robust construction no longer takes its exact path.
template <class Gt, class Cb = CGAL::Delaunay_triangulation_cell_base_3<Gt>>
class CellBase : public Cb {
public:
  using Vertex_handle = typename Cb::Vertex_handle;
  using Cell_handle = typename Cb::Cell_handle;
  using Point3 = typename Gt::Point_3;
  template <class TDS2> struct Rebind_TDS {
    using Cb2 = typename Cb::template Rebind_TDS<TDS2>::Other;
    using Other = CellBase<Gt, Cb2>;
  };
  using Cb::Cb;
  Point3 circumcenter(const Gt& gt = Gt()) const {
    const Point3* p[4];
    for (int i = 0; i < 4; ++i) p[i] = &this->vertex(i)->point();
    // Sorted by a network of five compare-exchanges (std::sort's call and
    // loop were a sixth of the cost).
    const auto order = [&p](int a, int b) {
      if (*p[b] < *p[a]) std::swap(p[a], p[b]);
    };
    order(0, 1), order(2, 3), order(0, 2), order(1, 3), order(1, 2);
    // Positively oriented, as the robust construction requires: its check
    // of the floating-point centre fails on the other orientation, and
    // every such cell took the exact path (8.7% of the bunny's instructions).
    if (gt.orientation_3_object()(*p[0], *p[1], *p[2], *p[3]) == CGAL::NEGATIVE) std::swap(p[2], p[3]);
    return gt.construct_circumcenter_3_object()(*p[0], *p[1], *p[2], *p[3]);
  }
  FacetRefs facet;
};

using Vb = CGAL::Triangulation_vertex_base_with_info_3<VInfo, GT>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, CellBase<GT>>;
using Tr = CGAL::Delaunay_triangulation_3<GT, Tds>;  // Compact_location: see doc/implicit2mesh.md
// CGAL's 72 bytes (65 used) + FacetRefs' 15 in their tail.
static_assert(sizeof(Tds::Cell) == 80, "a cell: FacetRefs in the tail padding of CGAL's cell base");
static_assert(sizeof(Tds::Vertex) == 56, "a vertex: CGAL's 40 bytes and VInfo's 16");
using Vh = Tr::Vertex_handle;
using Ch = Tr::Cell_handle;
using Facet = Tr::Facet;

inline Vec3 vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

// A finite facet's vertices by id. CGAL stores a facet on either side and
// vertex removal makes the side depend on addresses: every construction
// from a facet's vertices (site, normals, ratios) uses this order, so the
// last bits, and so the output, are the same on every run.
inline std::array<Vh, 3> facet_vertices(Ch c, int i) {
  std::array<Vh, 3> v{c->vertex((i + 1) & 3), c->vertex((i + 2) & 3), c->vertex((i + 3) & 3)};
  std::sort(v.begin(), v.end(), [](Vh a, Vh b) { return a->info().id < b->info().id; });
  return v;
}

// The surface centre x_t of a restricted facet (EdgeSurface's crossing).
inline Vec3 facet_center(const Facet& f) {
  const FacetInfo& fi = f.first->facet[f.second];
  return {fi.x[0], fi.x[1], fi.x[2]};
}


// Points a pass found on one state of W, each with its clearance (squared
// distance to W when found), for DELMESH's insert_batch.
using Candidates = std::vector<std::pair<Vec3, double>>;

// A set of vertex ids: a bit an id, visited in increasing order. Its users
// sort what they visit, so the order ids came in need not be kept: a list
// of them (4 bytes an id, and a byte per id for membership) held every
// vertex by the end of REFINE, twice (FacetCycle's and HandleDetection's
// sets), at the run's peak.
class IdSet {
public:
  void add(int id) {
    const std::size_t w = std::size_t(id) >> 6;
    if (w >= bits_.size()) bits_.resize(w + 1, 0);
    const std::uint64_t bit = std::uint64_t(1) << (id & 63);
    count_ += !(bits_[w] & bit);
    bits_[w] |= bit;
  }
  bool has(int id) const {
    const std::size_t w = std::size_t(id) >> 6;
    return w < bits_.size() && (bits_[w] >> (id & 63) & 1);
  }
  std::size_t size() const { return count_; }
  // f(id) for each id, in increasing order.
  template <class F> void for_each(F&& f) const {
    for (std::size_t w = 0; w < bits_.size(); ++w)
      for (std::uint64_t b = bits_[w]; b; b &= b - 1) f(int(w << 6) + __builtin_ctzll(b));
  }
  void clear() {
    std::fill(bits_.begin(), bits_.end(), 0);
    count_ = 0;
  }
  // An empty set's memory back to the heap.
  void release() {
    if (count_ == 0) std::vector<std::uint64_t>().swap(bits_);
  }

private:
  std::vector<std::uint64_t> bits_;
  std::size_t count_ = 0;
};

} // namespace imgmesh::surface_detail
