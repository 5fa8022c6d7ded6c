// The mesher's guarantees after REFINE: VoxelSides (every voxel centre
// next to an interface in a cell of its own label) and the rounds of
// refinement near the places the caller's certificate says fail.
#include "conforming/mesher.hpp"

#include "implicit/parallel.hpp"
#include "mesh/located_cells.hpp"
#include "util/error.hpp"
#include "util/memory.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>

namespace imgmesh {
namespace conforming_detail {

ConformingSurface Mesher::certified_rounds() {
  ConformingSurface out = output();
  // Rounds repair a patch sampled too coarsely (a small patch in pieces
  // where the curves around it are), not a labelling that disagrees with
  // K(X), where refining does not converge: they run while each round
  // leaves fewer failing places (a large patch's places are all its curve
  // edges: the brain map's went 4,986, 4,709, none), at most
  // certificate_rounds counted across calls; seg2tet calls again after its
  // cells, and a surface certified before them starts a fresh count there.
  std::size_t round_start = 0;  // the points when this call's last round began (0: none yet)
  while (o_.certificate && rounds_ < o_.certificate_rounds && !max_hit_) {
    // VoxelSides' cached cells (16 bytes a voxel next to an interface) not
    // held beside the certificate's peak: a round after it locates them
    // again (the same cells). seg2tet's cell stage refines again anyway.
    if (!o_.tets.on) {
      std::vector<SideVoxel>().swap(side_voxels_);
      release_free_memory();
    }
    const auto bad = o_.certificate(out.points, out.triangles, out.pairs);
    release_free_memory();  // the certificate's pages (its threads' arenas), before REFINE grows on them
    out.certified_as_is = true;
    // A certified surface that seg2tet's cells broke starts a fresh count.
    const std::size_t before = places_ == 0 ? std::size_t(-1) : places_;
    places_ = bad.size();
    if (o_.progress && !bad.empty())
      o_.progress("certificate: " + std::to_string(bad.size()) + " failing places after " + std::to_string(rounds_) +
                  " rounds");
    if (bad.empty() || bad.size() >= before) break;
    // A round that more than doubled the points and left more than half
    // the places is refining what does not converge (noisy maps at 7:1
    // anisotropy went 4K, 17K, 64K, 225K points over 14^3 voxels with the
    // places at 1367, 1355, 1309): no more rounds. (The brain's grew its
    // points 1.36x, 1.62x.)
    if (round_start > 0 && points_ > 2 * round_start && 2 * bad.size() > before) break;
    round_start = points_;
    if (!refine_near(bad)) break;
    ++rounds_;
    refine();
    out = output();
  }
  return out;
}

// VoxelSides' list runs along rows, jumping from one interface to the
// next and between rows and slices: from the voxel before, the walks
// crossed 26 cells each, 3/4 of them in jumps of over 20 voxels (the body
// map at 330x310x110). Per column (i, j) the cell of its last voxel so
// far: the floating-point walk starts at the nearest of the voxel before,
// the one before in its column (the slice before) and in the row before's
// column (7 cells a walk).
class WalkStarts {
public:
  explicit WalkStarts(const Geometry& x)
      : nx_(std::ptrdiff_t(x.size[0])), ny_(std::ptrdiff_t(x.size[1])), column_(x.size[0] * x.size[1]) {}
  // A cell nearer voxel v than the voxel before's (whose cell the caller
  // starts from), or Ch().
  Ch near(std::uint32_t v) const {
    const std::ptrdiff_t i = std::ptrdiff_t(v) % nx_, j = std::ptrdiff_t(v) / nx_ % ny_;
    Ch best;
    std::ptrdiff_t nearest = before_known_ ? apart2(before_, v) : std::numeric_limits<std::ptrdiff_t>::max();
    for (const std::ptrdiff_t at : {i + nx_ * j, j > 0 ? i + nx_ * (j - 1) : -1}) {
      if (at < 0) continue;
      const Seen& s = column_[std::size_t(at)];
      if (s.cell != Ch() && apart2(s.voxel, v) < nearest) best = s.cell, nearest = apart2(s.voxel, v);
    }
    return best;
  }
  // Voxel v is in cell c (the next one's voxel before).
  void seen(std::uint32_t v, Ch c) {
    column_[std::size_t(std::ptrdiff_t(v) % nx_ + nx_ * (std::ptrdiff_t(v) / nx_ % ny_))] = {c, v};
    before_ = v;
    before_known_ = true;
  }
  // The next voxel's start is not the voxel before's cell (a thread's next chunk).
  void forget_before() { before_known_ = false; }

private:
  struct Seen {
    Ch cell;
    std::uint32_t voxel = 0;
  };
  std::ptrdiff_t apart2(std::uint32_t a, std::uint32_t b) const {
    const std::ptrdiff_t di = std::ptrdiff_t(a) % nx_ - std::ptrdiff_t(b) % nx_,
                         dj = std::ptrdiff_t(a) / nx_ % ny_ - std::ptrdiff_t(b) / nx_ % ny_,
                         dk = std::ptrdiff_t(a) / nx_ / ny_ - std::ptrdiff_t(b) / nx_ / ny_;
    return di * di + dj * dj + dk * dk;
  }
  std::ptrdiff_t nx_, ny_;
  std::vector<Seen> column_;
  std::uint32_t before_ = 0;
  bool before_known_ = false;  // the first voxel's walk starts where the caller says
};

// Every voxel centre next to an interface in a cell of its own label.
void Mesher::voxel_sides() {
  // The voxels next to an interface, each once, in the faces' order: the
  // same list every call.
  if (side_voxels_.empty()) {
    if (x_.count() > std::numeric_limits<std::uint32_t>::max())
      throw Error("the conforming mesher takes label maps of at most 2^32 voxels");
    // Two sweeps: the count (seen 1), then the list (seen 2), of one size.
    std::vector<char> seen(x_.count(), 0);
    std::size_t count = 0;
    for (int sweep = 1; sweep <= 2; ++sweep) {
      if (sweep == 2) side_voxels_.reserve(count);
      for (std::uint64_t key : k_.faces) {
        const auto q = k_.corner(InterfaceComplex::face_corner(key));
        const int a = InterfaceComplex::face_axis(key);
        for (int s = 0; s < 2; ++s) {
          std::array<std::ptrdiff_t, 3> v{std::ptrdiff_t(q[0]), std::ptrdiff_t(q[1]), std::ptrdiff_t(q[2])};
          v[a] -= s;
          if (!x_.inside(v[0], v[1], v[2])) continue;
          char& done = seen[x_.index(std::size_t(v[0]), std::size_t(v[1]), std::size_t(v[2]))];
          if (done == sweep) continue;
          done = char(sweep);
          if (sweep == 1) ++count;
          else side_voxels_.push_back({Ch(), 0, std::uint32_t(x_.index(std::size_t(v[0]), std::size_t(v[1]), std::size_t(v[2])))});
        }
      }
    }
  }
  const auto& cells = tr_.tds().cells();
  // The cell that held the centre strictly inside at the last call, still
  // there (its uid unchanged: uids are never reused): the one locate would
  // find, and hint_ as locate leaves it, without the walk.
  auto cached = [&](const SideVoxel& sv) {
    return sv.cell != Ch() && cells.is_used(sv.cell) && sv.cell->info().uid == sv.uid;
  };
  auto centre_of = [&](std::uint32_t v) {
    return voxel_centre(std::ptrdiff_t(v % x_.size[0]), std::ptrdiff_t(v / x_.size[0] % x_.size[1]),
                        std::ptrdiff_t(v / x_.size[0] / x_.size[1]));
  };
  // A voxel whose cached cell is gone located (from start; the
  // floating-point walk from starts->near when given), its entry refreshed.
  auto locate_voxel = [&](SideVoxel& sv, Ch start, const WalkStarts* starts, Tr::Locate_type& lt, int& li, int& lj) {
    const Ch c = locate_from(tr_, pt(centre_of(sv.voxel)), lt, li, lj, start, starts ? starts->near(sv.voxel) : Ch());
    const bool keep = lt == Tr::CELL && c->info().uid != 0;
    sv.cell = keep ? c : Ch();
    sv.uid = keep ? c->info().uid : 0;
    return c;
  };
  // Those voxels located first on the threads (the triangulation only
  // read; each voxel's entry its own): where one cell holds the centre
  // strictly inside, that cell whatever the walk's start, the entry the
  // loop below reads as the cell it would locate. Elsewhere (on a facet,
  // edge or vertex, where the exact walk's start decides) the entry is left
  // empty, for the loop to locate from the voxel before, as ever: the same
  // cells, the same candidates in the same order, whatever the threads.
  const unsigned threads = implicit_detail::resolve_threads(o_.threads);
  if (threads > 1) {
    std::vector<std::unique_ptr<WalkStarts>> starts(threads);
    implicit_detail::parallel_for(long(side_voxels_.size()), threads, [&](long lo, long hi, unsigned t) {
      if (!starts[t]) starts[t] = std::make_unique<WalkStarts>(x_);
      WalkStarts& s = *starts[t];
      s.forget_before();
      Ch hint = hint_;
      for (long n = lo; n < hi; ++n) {
        SideVoxel& sv = side_voxels_[std::size_t(n)];
        Tr::Locate_type lt;
        int li, lj;
        hint = cached(sv) ? sv.cell : locate_voxel(sv, hint, &s, lt, li, lj);
        s.seen(sv.voxel, hint);
      }
    });
  }
  // The loop's own starts when it locates them all (with threads, the few
  // left walk from the voxel before).
  std::optional<WalkStarts> starts;
  if (threads == 1) starts.emplace(x_);
  for (SideVoxel& sv : side_voxels_) {
    const auto i = std::ptrdiff_t(sv.voxel % x_.size[0]), j = std::ptrdiff_t(sv.voxel / x_.size[0] % x_.size[1]),
               k = std::ptrdiff_t(sv.voxel / x_.size[0] / x_.size[1]);
    const Vec3 p = voxel_centre(i, j, k);
    Ch c;
    if (cached(sv)) {
      c = sv.cell;
      hint_ = c;
    } else {
      Tr::Locate_type lt;
      int li, lj;
      c = locate_voxel(sv, hint_, starts ? &*starts : nullptr, lt, li, lj);
      hint_ = c;
      // On a facet, edge or vertex of W: every cell there must be its label.
      if (lt != Tr::CELL && lt != Tr::OUTSIDE_CONVEX_HULL) {
        located_cells(tr_, c, lt, li, lj, cells_);
        const std::int32_t own = voxel_label(i, j, k);
        for (Ch n : cells_)
          if (label(n) != own) c = n;
      }
    }
    if (starts) starts->seen(sv.voxel, hint_);
    const std::int32_t own = voxel_label(i, j, k);
    if (label(c) == own) continue;
    Candidate cand;
    if (!f_.first_change(p, centre(c), cand.x, o_.step)) continue;
    cand.step = kVoxelSide;
    cand.priority = dist2(cand.x, p);
    sides_.push_back(cand);
  }
}

// The surface centres of the restricted facets in the voxels within one
// of the voxel holding each place.
bool Mesher::refine_near(const std::vector<Vec3>& places) {
  std::vector<char> near(x_.count(), 0);
  for (const Vec3& p : places) {
    const Vec3 q = x_.continuous_index(p);
    const auto i = std::ptrdiff_t(std::floor(q[0] + 0.5)), j = std::ptrdiff_t(std::floor(q[1] + 0.5)),
               k = std::ptrdiff_t(std::floor(q[2] + 0.5));
    for (std::ptrdiff_t dz = -1; dz <= 1; ++dz)
      for (std::ptrdiff_t dy = -1; dy <= 1; ++dy)
        for (std::ptrdiff_t dx = -1; dx <= 1; ++dx)
          if (x_.inside(i + dx, j + dy, k + dz))
            near[x_.index(std::size_t(i + dx), std::size_t(j + dy), std::size_t(k + dz))] = 1;
  }
  // A facet's surface centre lies on its Voronoi edge, whose ends' voxel
  // box (rounded as the centre is) holds its voxel: facets with no near
  // voxel in that box are passed over without the walk along the edge.
  auto may_be_near = [&](const Vec3& a, const Vec3& b) {
    const Vec3 qa = x_.continuous_index(a), qb = x_.continuous_index(b);
    std::ptrdiff_t lo[3], hi[3];
    std::size_t volume = 1;
    for (int m = 0; m < 3; ++m) {
      lo[m] = std::max<std::ptrdiff_t>(0, std::ptrdiff_t(std::floor(std::min(qa[m], qb[m]) + 0.5)));
      hi[m] = std::min<std::ptrdiff_t>(std::ptrdiff_t(x_.size[m]) - 1, std::ptrdiff_t(std::floor(std::max(qa[m], qb[m]) + 0.5)));
      if (!(lo[m] <= hi[m])) return false;
      volume *= std::size_t(hi[m] - lo[m] + 1);
    }
    if (volume > 512) return true;
    for (std::ptrdiff_t k = lo[2]; k <= hi[2]; ++k)
      for (std::ptrdiff_t j = lo[1]; j <= hi[1]; ++j)
        for (std::ptrdiff_t i = lo[0]; i <= hi[0]; ++i)
          if (near[x_.index(std::size_t(i), std::size_t(j), std::size_t(k))]) return true;
    return false;
  };
  // CGAL gives each facet from the cell of the lower address: the walk
  // goes from the smaller circumcentre (uid on a tie) and the centres are
  // sorted, the same every run (the walk's bisection depends on its
  // direction, the vertex ids on the order). They go in larger surface
  // balls first, each unless a vertex is already within a quarter of its
  // ball's radius: the centres of two neighbouring facets can lie 1e-4
  // voxel apart, and QUALITY would then grade the mesh down to them
  // (hundreds of triangles, and seg2tet's slivers, in a thousandth of a voxel).
  // (squared radius, centre, a vertex of its facet: vertices stay, its
  // cells a walk's start near the centre; from hint_, the last point
  // inserted, in this order of radii, the walks crossed the mesh: a sixth
  // of the brain map's time)
  struct Centre {
    double r2;
    Vec3 x;
    Vh v;
  };
  std::vector<Centre> centres;
  for (auto f = tr_.finite_facets_begin(); f != tr_.finite_facets_end(); ++f) {
    Ch c = f->first, n = c->neighbor(f->second);
    if (tr_.is_infinite(c) || tr_.is_infinite(n) || label(c) == label(n) || !may_be_near(centre(c), centre(n)))
      continue;
    if (std::make_pair(centre(n), n->info().uid) < std::make_pair(centre(c), c->info().uid)) std::swap(c, n);
    const int i = c->index(n);
    Vec3 x;
    if (!surface_centre(c, i, x)) continue;
    const Vec3 q = x_.continuous_index(x);
    const auto vi = std::ptrdiff_t(std::floor(q[0] + 0.5)), vj = std::ptrdiff_t(std::floor(q[1] + 0.5)),
               vk = std::ptrdiff_t(std::floor(q[2] + 0.5));
    if (x_.inside(vi, vj, vk) && near[x_.index(std::size_t(vi), std::size_t(vj), std::size_t(vk))])
      centres.push_back({dist2(x, vec(c->vertex((i + 1) & 3)->point())), x, c->vertex((i + 1) & 3)});
  }
  std::sort(centres.begin(), centres.end(),
            [](const Centre& a, const Centre& b) { return a.r2 != b.r2 ? a.r2 > b.r2 : a.x < b.x; });
  bool any = false;
  for (const Centre& c : centres) any = insert(c.x, kCertificate, Ch(), c.r2 / 16, c.v->cell()) || any;
  return any;
}

} // namespace conforming_detail
} // namespace imgmesh
