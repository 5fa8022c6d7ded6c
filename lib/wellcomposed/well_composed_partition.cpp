// The multi-label repair (issue 36), chapter 5's algorithm with labels for
// colours.
//
// A configuration is an instance (square or block, label L): a C1 of L in a
// square N_x(r), N_y(r), N_z(r), or a C2 of L in a block N(r). It is
// resolved by relabelling one voxel of that square or block, among the
// moves that remove it (C1, L on one diagonal: a voxel of the other diagonal
// becomes L, or an L voxel takes a label of the other diagonal; C2, L on two
// opposite corners: one of them takes a label of the other six, or one of
// the six becomes L; C2, L on six: one of the other two becomes L, or an L
// voxel takes a label of those two). Of those, the move chosen keeps every
// kept label's last voxel, creates no configuration if one can, removes the
// most configurations around it, creates the fewest (the thesis's rules
// (1)-(3) with B(r) made of single moves), the first in a fixed order on
// ties: deterministic. Configurations it creates lie in the 8 blocks
// holding the voxel: those go on the queue R.
//
// Which moves are allowed. Labels have a priority (rank): the background
// lowest, then by default the labels from the most voxels to the fewest, so
// small structures grow rather than shrink (as the binary add mode: a thin
// vessel stays connected); PartitionOptions::priority reverses it. An up
// move gives a voxel a label of higher rank. A down move gives a voxel of
// label X a lower-ranked label Y, and is allowed only where X has nothing
// at stake and nothing is created: none of X's configurations around the
// voxel goes (X does not thin where it is critical), none of X's or Y's
// appears, Y is not the background (a voxel given to it would thin X or
// the foreground, the union of the labels, at a configuration), and the
// voxel never moved down before. So a label loses a voxel at one of its own configurations only
// to a label of higher priority, and labels only grow into the background,
// as in the binary add mode; the down moves let Y grow where X gives a
// voxel for free, in place of an up move that would create configurations
// (on the bundled brain map and the Voronoi maps of scripts/bench img2wc,
// 5-14% fewer changes than up moves alone).
//
// Why it terminates. An up move exists for every configuration: C1 of L
// with a, b on the other diagonal: if rank L > rank a, a's voxel becomes L;
// else an L voxel becomes a. C2 of L on two corners: if a label x of the six
// ranks above L, a corner becomes x; else one of the six becomes L. C2 of L
// on six, a, b on the other two: a's voxel becomes L if L ranks above a,
// else an L voxel becomes a. Every up move raises the sum of the ranks of
// all voxels by at least 1; the down moves, at most one a voxel, lower it by
// less than 2K each (K labels). A label whose last voxel every move would
// take is raised once to the top rank (then a move keeping it exists: an L
// voxel takes that label); that raises the sum too, and happens at most
// once a label. The sum lies in [0, N (2K)] for N voxels, so there are at
// most N (2K) + N (2K) up moves and N down moves: at most 4K + 1 a voxel
// on average, and each queue entry is a block made critical by a move (at
// most 8 a move) or one of the N blocks of the scan: linear in voxels +
// moves.
//
// Why no configuration is left. Every critical block is either still ahead
// in the scan or on the queue (a move changes only the 8 blocks holding its
// voxel, and queues them), and a block leaves the scan or the queue only
// when it holds none. At the end both are empty. The count is redone on the
// output anyway (PartitionResult::output).
//
// The border. Where a label touches a side the grid grows by one background
// voxel, so every side layer is background. A square with two side-layer
// voxels, or a block with four, holds no configuration of any label, so no
// move ever involves a side voxel: the border stays background, and blocks
// reaching outside the grid are never critical.
//
// Then, in 3D (PartitionOptions::generic), a second scan for the
// configurations a well-composed partition may keep but no smooth partition
// has, so no conforming mesh can match them (issue 40: on the noisy brain
// map they were 300 of the 427 K(X) patches its conforming mesh got wrong):
// a square of four labels (a voxel edge where four labels meet: any smooth
// partition there lets one diagonal pair touch, an extra patch) and a block
// whose centre corner pinches a patch (two fans of one pair's faces there:
// a smooth partition opens or splits it). Each is ended by one voxel of
// the square (block) taking a neighbour's label there, among the moves
// that end it, create no C1 or C2, keep every kept label and are up or
// allowed down moves, chosen as above. The first phase's result stays
// well-composed and every move still raises the rank sum (or is a voxel's
// one down move): it terminates. A configuration no such move ends is
// left, the block retried after the moves near it while any are made; then
// retried once more allowing moves that create C1 or C2, which the drain
// ends as in the first phase (still up or allowed down moves: it
// terminates; on the noisy brain map this ends the last 27 four-label
// edges and 6 pinches for 72 more changes). Those left (every move takes a
// kept label's last voxel) are counted by K(X) (its pinches, its curves
// of four labels).
//
// Last, every changed voxel goes back to its input label when that creates
// no configuration in its 8 blocks (and keeps every kept label), once, in
// the order of the changes: fewer changes, still none left.
#include "wellcomposed/well_composed_partition.hpp"

#include "util/error.hpp"
#include "wellcomposed/critical_configuration.hpp"
#include "wellcomposed/label_grid.hpp"

#include <algorithm>
#include <numeric>
#include <string>
#include <tuple>
#include <unordered_set>

namespace imgmesh {
namespace {

using wellcomposed_detail::critical_configurations;
using wellcomposed_detail::mask_of;

constexpr unsigned kFace[3] = {0x55u, 0x33u, 0x0fu};  // N_x(r), N_y(r), N_z(r) as block bits

inline int popcount(unsigned v) { return __builtin_popcount(v); }
inline std::uint8_t flags(unsigned mask) { return critical_configurations(std::uint8_t(mask)); }

// The generic configurations of a block (3D; see the header): bit a (0-2)
// when its square N_a(r) holds four labels (a voxel edge where four labels
// meet), bit 3 when some label pair's faces at the block's centre corner,
// joined through the corner's six edges, fall in two classes or more (a
// pinched patch).
template <class T> unsigned generic_configurations(const T b[8]) {
  unsigned out = 0;
  for (int a = 0; a < 3; ++a) {
    T q[4];
    int n = 0;
    for (int k = 0; k < 8; ++k)
      if (kFace[a] >> k & 1u) q[n++] = b[k];
    if (q[0] != q[1] && q[0] != q[2] && q[0] != q[3] && q[1] != q[2] && q[1] != q[3] && q[2] != q[3]) out |= 1u << a;
  }
  // The 12 faces (k, k | bit) with bit k clear; two faces of one pair are
  // joined when both lie around one of the corner's half edges (the four
  // voxels on one side of the block along one axis). The tables once.
  struct Faces {
    int face_of[8][8];
    int fk[12], fl[12];
    Faces() {
      int nf = 0;
      for (int bit = 1; bit < 8; bit <<= 1)
        for (int k = 0; k < 8; ++k)
          if (!(k & bit)) {
            face_of[k][k | bit] = face_of[k | bit][k] = nf;
            fk[nf] = k, fl[nf++] = k | bit;
          }
    }
  };
  static const Faces tables;
  const auto& face_of = tables.face_of;
  const int* fk = tables.fk;
  const int* fl = tables.fl;
  int parent[12];
  for (int f = 0; f < 12; ++f) parent[f] = f;
  auto find = [&](int f) {
    while (parent[f] != f) f = parent[f] = parent[parent[f]];
    return f;
  };
  auto same_pair = [&](int f, int g) {
    return (b[fk[f]] == b[fk[g]] && b[fl[f]] == b[fl[g]]) || (b[fk[f]] == b[fl[g]] && b[fl[f]] == b[fk[g]]);
  };
  int faces = 0;
  for (int f = 0; f < 12; ++f) faces += b[fk[f]] != b[fl[f]];
  if (faces < 4) return out;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      // The four voxels with bit `axis` == side, in cyclic order around the half edge.
      const int u = 1 << ((axis + 1) % 3), w = 1 << ((axis + 2) % 3), base = side << axis;
      const int ring[4] = {base, base | u, base | u | w, base | w};
      for (int i = 0; i < 4; ++i) {
        const int f = face_of[ring[i]][ring[(i + 1) % 4]];
        if (b[fk[f]] == b[fl[f]]) continue;
        for (int j = i + 1; j < 4; ++j) {
          const int g = face_of[ring[j]][ring[(j + 1) % 4]];
          if (b[fk[g]] != b[fl[g]] && same_pair(f, g)) parent[find(f)] = find(g);
        }
      }
    }
  for (int f = 0; f < 12; ++f) {
    if (b[fk[f]] == b[fl[f]]) continue;
    for (int g = f + 1; g < 12; ++g)
      if (b[fk[g]] != b[fl[g]] && same_pair(f, g) && find(f) != find(g)) return out | 8u;
  }
  return out;
}

// One configuration: label l's code m in block r, and which (0-2: C1 on
// N_x, N_y, N_z; 3: C2; 4-6: four labels on N_x, N_y, N_z; 7: a pinch).
struct Instance {
  std::size_t r;
  unsigned label, m;
  int kind;
};

struct Move {
  std::size_t voxel;
  unsigned from, to;
  int created = 0, removed = 0;
  bool kills = false;  // takes the last voxel of a kept label
  bool down = false;   // to a label of lower rank
  bool critical = false;  // creates a C1 or C2
  bool better_than(const Move& o) const {
    return std::make_tuple(kills, created > 0, -removed, created) <
           std::make_tuple(o.kills, o.created > 0, -o.removed, o.created);
  }
};

template <class T> class PartitionRepair {
public:
  // grid: nx x ny x nz label indices whose side layers are 0; 2D: nz == 2,
  // the image in layer 0, layer 1 background.
  PartitionRepair(T* grid, std::size_t nx, std::size_t ny, std::size_t nz, bool planar, bool generic,
                  std::vector<unsigned> rank, std::vector<std::size_t> count, std::vector<char> keep,
                  std::size_t max_steps)
      : v_(grid), n_{nx, ny, nz}, sy_(nx), sz_(nx * ny), blocks_(planar ? 4 : 8), want_generic_(generic && !planar),
        rank_(std::move(rank)),
        top_(unsigned(rank_.size())), count_(std::move(count)), keep_(std::move(keep)), raised_(rank_.size(), 0),
        max_steps_(max_steps) {
    for (int k = 0; k < 8; ++k) off_[k] = std::size_t(k & 1) + std::size_t((k >> 1) & 1) * sy_ + std::size_t((k >> 2) & 1) * sz_;
  }

  // Figures 5.1 and 5.2: scan the blocks; resolve each critical one, then
  // drain R (blocks made critical by the moves) before the scan goes on.
  void run() {
    if (n_[0] < 2 || n_[1] < 2 || n_[2] < 2 || max_steps_ == 0) return;
    scan();
    if (!want_generic_) return;
    generic_ = true;
    scan();
    // A configuration left for want of a move may have one after the moves
    // near it: again over those, while any moves; once none does, again
    // letting the moves create C1 or C2 (the drain then ends those).
    for (std::size_t before = steps + 1; !stuck_.empty() && steps < max_steps_;) {
      if (before == steps) {
        if (lenient_) break;
        lenient_ = true;
      }
      before = steps;
      std::vector<std::size_t> left(stuck_.begin(), stuck_.end());
      std::sort(left.begin(), left.end());
      stuck_.clear();
      for (std::size_t r : left) lenient_ ? try_undoably(r) : resolve_and_drain(r);
    }
  }

  // One scan over the blocks (phase 1: C1 and C2; phase 2: the generic
  // configurations, by moves that create no C1 or C2).
  void scan() {
    for (std::size_t z = 0; z + 1 < n_[2]; ++z)
      for (std::size_t y = 0; y + 1 < n_[1]; ++y) {
        const std::size_t row = sy_ * y + sz_ * z;
        for (std::size_t x = 0; x + 1 < n_[0]; ++x) {
          const std::size_t r = row + x;
          if (x + 8 <= n_[0] && wellcomposed_detail::uniform_rows(v_ + r, v_ + r + sy_, v_ + r + sz_, v_ + r + sz_ + sy_)) {
            x += 6;  // blocks x .. x+6 hold one label
            continue;
          }
          resolve_and_drain(r);
          if (steps >= max_steps_) return;
        }
      }
  }

  // A changed voxel goes back to its input label when none of its blocks
  // becomes critical (only those see it); once each, in the order of change.
  void prune() {
    std::vector<std::size_t> order(log_.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return log_[a].first < log_[b].first; });
    std::vector<std::size_t> first;  // log positions of each voxel's first change
    for (std::size_t i = 0; i < order.size(); ++i)
      if (i == 0 || log_[order[i]].first != log_[order[i - 1]].first) first.push_back(order[i]);
    std::sort(first.begin(), first.end());
    for (std::size_t pos : first) {
      const std::size_t i = log_[pos].first;
      const unsigned input = log_[pos].second, now = v_[i];
      if (now == input || (keep_[now] && count_[now] == 1)) continue;
      bool ok = true;
      for (int k = 0; k < blocks_ && ok; ++k) {
        T b[8];
        load(i - off_[k], b);
        const unsigned g0 = generic(b);
        b[k] = T(input);
        ok = !flags(mask_of(b, T(input))) && !flags(mask_of(b, T(now))) && !(generic(b) & ~g0);
      }
      if (ok) set(i, input);
    }
    log_.clear();
  }

  std::size_t steps = 0, raised = 0;
  const std::vector<std::size_t>& count() const { return count_; }

private:
  void load(std::size_t r, T b[8]) const {
    for (int k = 0; k < 8; ++k) b[k] = v_[r + off_[k]];
  }

  // The first configuration of block r (labels in the order of their first
  // voxel; C1 on N_x, N_y, N_z, then C2), if any.
  bool first_instance(std::size_t r, Instance& in) const {
    T b[8];
    load(r, b);
    unsigned done = 0;
    for (int k = 0; k < 8; ++k) {
      if (done >> k & 1u) continue;
      const unsigned m = mask_of(b, b[k]);
      if (m == 0xffu) return false;
      done |= m;
      if (const std::uint8_t f = flags(m)) {
        in = {r, unsigned(b[k]), m, __builtin_ctz(f)};
        return true;
      }
    }
    if (const unsigned g = generic(b); g && !stuck_.count(r)) {
      in = {r, 0, 0, 4 + __builtin_ctz(g)};
      return true;
    }
    return false;
  }

  unsigned generic(const T b[8]) const { return generic_ ? generic_configurations(b) : 0u; }
  bool on_side(std::size_t i) const {
    const std::size_t x = i % sy_, y = i / sy_ % n_[1], z = i / sz_;
    return x == 0 || y == 0 || z == 0 || x + 1 == n_[0] || y + 1 == n_[1] || z + 1 == n_[2];
  }

  void resolve(std::size_t r) {
    Instance in;
    while (steps < max_steps_ && first_instance(r, in)) fix(in);
  }
  // Block r, then R (the blocks its moves made critical) until empty.
  void resolve_and_drain(std::size_t r) {
    resolve(r);
    for (std::size_t head = 0; head < queue_.size(); ++head) resolve(queue_[head]);
    queue_.clear();
  }

  // Block r and the drain, undone when a move took a kept label's last
  // voxel (the drain of a C1 the lenient move made can, where the first
  // phase could not) or the step cap cut the drain short.
  void try_undoably(std::size_t r) {
    const std::size_t mark = log_.size(), steps0 = steps, raised0 = raised;
    const unsigned top0 = top_;
    undo_ = {};
    resolve_and_drain(r);
    if (!undo_.killed && steps < max_steps_) return;
    for (std::size_t i = log_.size(); i-- > mark;) set(log_[i].first, log_[i].second);
    log_.resize(mark);
    for (std::size_t i : undo_.fell) fell_.erase(i);
    for (auto it = undo_.ranks.rbegin(); it != undo_.ranks.rend(); ++it) rank_[it->first] = it->second, raised_[it->first] = 0;
    steps = steps0, raised = raised0, top_ = top0;
    stuck_.insert(r);
  }

  // Configurations created and removed by voxel i taking label `to`: only
  // the codes of its old and new label change, in the blocks holding i.
  Move evaluate(std::size_t i, unsigned to) const {
    Move mv{i, v_[i], to};
    for (int k = 0; k < blocks_; ++k) {
      T b[8];
      load(i - off_[k], b);
      const unsigned bit = 1u << k, ma = mask_of(b, T(mv.from)), mb = mask_of(b, T(to));
      const unsigned fa0 = flags(ma), fa1 = flags(ma & ~bit), fb0 = flags(mb), fb1 = flags(mb | bit);
      mv.created += popcount(fa1 & ~fa0) + popcount(fb1 & ~fb0);
      mv.critical = mv.critical || (fa1 & ~fa0) || (fb1 & ~fb0);
      mv.removed += popcount(fa0 & ~fa1) + popcount(fb0 & ~fb1);
      if (generic_) {
        const unsigned g0 = generic_configurations(b);
        b[k] = T(to);
        const unsigned g1 = generic_configurations(b);
        mv.created += popcount(g1 & ~g0);
        mv.removed += popcount(g0 & ~g1);
      }
    }
    mv.kills = keep_[mv.from] && count_[mv.from] == 1;
    return mv;
  }

  // A down move's condition (see the header): voxel i's label keeps all its
  // configurations around i, and `to` gains none.
  bool may_yield(std::size_t i, unsigned to) const {
    const unsigned from = v_[i];
    for (int k = 0; k < blocks_; ++k) {
      T b[8];
      load(i - off_[k], b);
      const unsigned bit = 1u << k, ma = mask_of(b, T(from)), mb = mask_of(b, T(to));
      if (flags(ma) != flags(ma & ~bit) || (flags(mb | bit) & ~flags(mb))) return false;
    }
    return true;
  }

  // The moves of the header that remove `in`: up, or down as allowed.
  int moves(const Instance& in, Move out[24]) const {
    int n = 0;
    auto consider = [&](int k, unsigned to) {
      const std::size_t i = in.r + off_[k];
      if (rank_[to] > rank_[v_[i]]) {
        out[n++] = evaluate(i, to);
      } else if (to != 0 && !fell_.count(i) && may_yield(i, to)) {
        out[n] = evaluate(i, to);
        out[n++].down = true;
      }
    };
    // Labels of the voxels in `set`, each once.
    auto labels_of = [&](unsigned set, unsigned* ls) {
      int c = 0;
      for (unsigned s = set; s; s &= s - 1) {
        const unsigned l = v_[in.r + off_[__builtin_ctz(s)]];
        if (std::find(ls, ls + c, l) == ls + c) ls[c++] = l;
      }
      return c;
    };
    unsigned ls[6];
    if (in.kind >= 4) {
      // Four labels on a square: a voxel takes the label of one of its two
      // neighbours there; a pinch: a voxel takes one of its three
      // neighbours' in the block, where that ends the pinch. The lowest
      // ranked of a square has an up move to each; a pinch may have none
      // (then it is left, and counted).
      const unsigned set = in.kind < 7 ? kFace[in.kind - 4] : 0xffu;
      for (unsigned s = set; s; s &= s - 1) {
        const int k = __builtin_ctz(s);
        if (on_side(in.r + off_[k])) continue;
        for (int bit = 1; bit < 8; bit <<= 1) {
          if (!(set >> (k ^ bit) & 1u)) continue;
          const unsigned to = v_[in.r + off_[k ^ bit]];
          if (to == v_[in.r + off_[k]]) continue;
          const int before = n;
          consider(k, to);
          if (n > before && in.kind == 7) {
            T b[8];
            load(in.r, b);
            b[k] = T(to);
            if (generic_configurations(b) & 8u) --n;
          }
        }
      }
      return n;
    }
    if (in.kind < 3) {  // C1: L on one diagonal of the face, two others on the other
      const unsigned face = kFace[in.kind], diag = in.m & face, other = face & ~in.m;
      const int c = labels_of(other, ls);
      for (unsigned s = other; s; s &= s - 1) consider(__builtin_ctz(s), in.label);
      for (unsigned s = diag; s; s &= s - 1)
        for (int j = 0; j < c; ++j) consider(__builtin_ctz(s), ls[j]);
    } else if (popcount(in.m) == 2) {  // C2, L on two opposite corners
      const unsigned six = ~in.m & 0xffu;
      const int c = labels_of(six, ls);
      for (unsigned s = in.m; s; s &= s - 1)
        for (int j = 0; j < c; ++j) consider(__builtin_ctz(s), ls[j]);
      for (unsigned s = six; s; s &= s - 1) consider(__builtin_ctz(s), in.label);
    } else {  // C2, L on six
      const unsigned two = ~in.m & 0xffu;
      const int c = labels_of(two, ls);
      for (unsigned s = two; s; s &= s - 1) consider(__builtin_ctz(s), in.label);
      for (unsigned s = in.m; s; s &= s - 1)
        for (int j = 0; j < c; ++j) consider(__builtin_ctz(s), ls[j]);
    }
    return n;
  }

  void fix(const Instance& in) {
    Move mv[24];
    int n = moves(in, mv);
    if (in.kind >= 4) {
      // A generic configuration is ended by a move that keeps every kept
      // label and (but in the last retries) creates no C1 or C2: one that
      // no such move ends is left (and counted on the output).
      const bool lenient = lenient_;
      n = int(std::remove_if(mv, mv + n, [lenient](const Move& m) { return m.kills || (m.critical && !lenient); }) - mv);
      if (n == 0) {
        stuck_.insert(in.r);
        return;
      }
    }
    if (n == 0) throw Error("internal: no upward move for a critical configuration");  // see the header
    int best = 0;
    for (int i = 1; i < n; ++i)
      if (mv[i].better_than(mv[best])) best = i;
    if (mv[best].kills && !raised_[mv[best].from]) {
      // Every move takes a kept label's last voxel: raise that label to the
      // top once, then moves keeping it exist (see the header).
      raised_[mv[best].from] = 1;
      if (lenient_) undo_.ranks.emplace_back(mv[best].from, rank_[mv[best].from]);
      rank_[mv[best].from] = top_++;
      ++raised;
      return;
    }
    if (mv[best].down && fell_.insert(mv[best].voxel).second && lenient_) undo_.fell.push_back(mv[best].voxel);
    undo_.killed = undo_.killed || mv[best].kills;
    set(mv[best].voxel, mv[best].to);
    log_.emplace_back(mv[best].voxel, T(mv[best].from));
    ++steps;
    for (int k = 0; k < blocks_; ++k) queue_.push_back(mv[best].voxel - off_[k]);
  }

  void set(std::size_t i, unsigned to) {
    --count_[v_[i]];
    ++count_[to];
    v_[i] = T(to);
  }

  T* v_;
  std::size_t n_[3], sy_, sz_, off_[8];
  int blocks_;  // blocks holding a voxel: 8, or 4 in 2D (those below the image see only background)
  bool want_generic_;     // 3D and asked for: a second phase for the generic configurations
  bool generic_ = false;  // in that phase: four-label squares and pinches are configurations too
  bool lenient_ = false;  // in its last retries: a move may create C1 or C2
  std::vector<unsigned> rank_;
  unsigned top_;
  std::vector<std::size_t> count_;
  std::vector<char> keep_, raised_;
  std::size_t max_steps_;
  std::unordered_set<std::size_t> fell_;          // voxels that made their down move
  std::unordered_set<std::size_t> stuck_;         // blocks with a pinch no move ends
  std::vector<std::size_t> queue_;                // R
  std::vector<std::pair<std::size_t, T>> log_;    // (voxel, label before) of every move
  struct Undo {  // what try_undoably restores besides the moves
    bool killed = false;
    std::vector<std::size_t> fell;
    std::vector<std::pair<unsigned, unsigned>> ranks;  // (label, rank before its raise)
  } undo_;
};

// Ranks: background 0, then the labels from the most input voxels to the
// fewest (Smaller: small labels win), or the reverse (Larger); ties: the
// larger value ranks higher.
std::vector<unsigned> label_ranks(const std::vector<std::size_t>& voxels, PartitionOptions::Priority priority) {
  std::vector<unsigned> order(voxels.size());
  std::iota(order.begin(), order.end(), 0u);
  const bool smaller = priority == PartitionOptions::Priority::Smaller;
  std::stable_sort(order.begin() + 1, order.end(), [&](unsigned a, unsigned b) {
    return smaller ? voxels[a] > voxels[b] : voxels[a] < voxels[b];
  });
  std::vector<unsigned> rank(voxels.size());
  for (std::size_t i = 0; i < order.size(); ++i) rank[order[i]] = unsigned(i);
  return rank;
}

} // namespace

namespace {

// The repair on the padded grid of dense indices (T: one byte up to 255
// labels, two above); fills res.image, res.output and the counts.
template <class T>
void repair_dense(LabelImage& in, const wellcomposed_detail::LabelValues& lv,
                  const wellcomposed_detail::Padding& pad, const PartitionOptions& opt, PartitionResult& res) {
  const bool planar = in.dimension == 2;
  const std::size_t nx = in.size[0] + pad.before[0] + pad.after[0], ny = in.size[1] + pad.before[1] + pad.after[1];
  const std::size_t nz = planar ? 2 : in.size[2] + pad.before[2] + pad.after[2];
  std::vector<T> grid(nx * ny * nz, T(0));
  auto at = [&](std::size_t x, std::size_t y, std::size_t z) {
    return x + pad.before[0] + nx * (y + pad.before[1] + ny * (z + pad.before[2]));
  };
  {
    std::int32_t last = 0;
    std::size_t index = 0;
    for (std::size_t z = 0; z < in.size[2]; ++z)
      for (std::size_t y = 0; y < in.size[1]; ++y) {
        const std::int32_t* row = &in.data[in.index(0, y, z)];
        T* out = &grid[at(0, y, z)];
        for (std::size_t x = 0; x < in.size[0]; ++x) {
          if (row[x] != last) index = lv.index_of(last = row[x]);
          out[x] = T(index);
        }
      }
  }
  const std::size_t K = lv.values.size();
  std::vector<char> keep(K, 0);
  for (std::size_t l = 1; l < K; ++l) keep[l] = lv.voxels[l] >= std::max<std::size_t>(opt.min_voxels, 1);
  std::vector<std::size_t> count(lv.voxels);
  count[0] += grid.size() - in.count();
  res.input.labels = lv.values;
  res.input.counts.assign(K, {});
  wellcomposed_detail::count_dense(grid.data(), nx, ny, nz, res.input.counts);  // outside = 0: the input's counts
  PartitionRepair<T> rep(grid.data(), nx, ny, nz, planar, opt.generic, label_ranks(lv.voxels, opt.priority), count,
                         keep, opt.max_steps);
  if (opt.repair) {
    rep.run();
    if (opt.prune) rep.prune();
  }
  res.steps = rep.steps;
  res.promotions = rep.raised;

  res.output.labels = lv.values;
  res.output.counts.assign(K, {});
  wellcomposed_detail::count_dense(grid.data(), nx, ny, nz, res.output.counts);
  // The output image, the changes, and the labels lost, from the grids;
  // without growth, in the input's own storage (a fresh image costs more
  // than the repair on a large grid).
  std::vector<std::size_t> now(K, 0);
  LabelImage out;
  if (!pad.any()) {
    out = std::move(in);
  } else {
    Geometry g = in.geometry();
    g.size = {nx, ny, planar ? 1 : nz};
    g.origin = in.world(-double(pad.before[0]), -double(pad.before[1]), -double(pad.before[2]));
    out = LabelImage(g);
  }
  for (std::size_t z = 0; z < in.size[2]; ++z)
    for (std::size_t y = 0; y < in.size[1]; ++y) {
      const std::size_t from = pad.any() ? in.index(0, y, z) : out.index(0, y, z), to = at(0, y, z);
      const std::int32_t* a = pad.any() ? &in.data[from] : &out.data[from];
      std::int32_t* b = &out.data[to];
      for (std::size_t x = 0; x < in.size[0]; ++x) {
        const T l = grid[to + x];
        const std::int32_t v = lv.values[l];
        ++now[l];
        if (a[x] != v) ++res.changes[{a[x], v}];
        b[x] = v;
      }
    }
  for (std::size_t l = 1; l < K; ++l)
    if (lv.voxels[l] && !now[l]) {
      res.lost.push_back(lv.values[l]);
      if (keep[l]) res.lost_protected.push_back(lv.values[l]);
    }
  res.image = std::move(out);
}

} // namespace

PartitionResult make_well_composed_partition(LabelImage in, const PartitionOptions& opt) {
  wellcomposed_detail::check_size(in, "make_well_composed_partition");
  if (in.data.size() != in.count()) throw Error("make_well_composed_partition: image data size mismatch");
  const wellcomposed_detail::LabelValues lv = wellcomposed_detail::label_values(in);
  const wellcomposed_detail::Padding pad = wellcomposed_detail::border_padding(in);
  PartitionResult res;
  res.options = opt;
  res.input_voxels = in.count();
  res.padded_before = pad.before;
  res.padded_after = pad.after;
  if (lv.values.size() <= 256) repair_dense<std::uint8_t>(in, lv, pad, opt, res);
  else repair_dense<std::uint16_t>(in, lv, pad, opt, res);
  for (const auto& [pair, n] : res.changes) res.changed += n;
  return res;
}

namespace {
std::vector<unsigned long long> triple(const std::array<std::size_t, 3>& a) { return {a[0], a[1], a[2]}; }
} // namespace

Json PartitionResult::to_json() const {
  Json j = Json::object();
  j["dimension"] = image.dimension;
  j["voxels"] = input_voxels;
  j["labels"] = input.labels.size() - 1;
  j["label_values"] = std::vector<std::int32_t>(input.labels.begin() + 1, input.labels.end());
  j["min_voxels"] = options.min_voxels;
  j["priority"] = options.priority == PartitionOptions::Priority::Smaller ? "smaller" : "larger";
  const Json in = input.to_json();
  j["c1"] = in.at("c1");
  j["c2"] = in.at("c2");
  j["labels_with_configurations"] = input.labels_with_configurations();
  j["changed"] = changed;
  j["steps"] = steps;
  j["promotions"] = promotions;
  // Per (from, to) pair, and per label: voxels that left it, voxels it gained.
  Json pairs = Json::array();
  std::map<std::int32_t, std::pair<std::size_t, std::size_t>> per;
  for (const auto& [ab, n] : changes) {
    Json p = Json::object();
    p["from"] = ab.first;
    p["to"] = ab.second;
    p["voxels"] = n;
    pairs.push_back(p);
    per[ab.first].first += n;
    per[ab.second].second += n;
  }
  j["changes"] = pairs;
  Json labels = Json::object();
  for (const auto& [l, n] : per) {
    Json p = Json::object();
    p["lost"] = n.first;
    p["gained"] = n.second;
    labels[std::to_string(l)] = p;
  }
  j["changed_per_label"] = labels;
  j["input_per_label"] = in.at("per_label");
  j["output_size"] = triple(image.size);
  j["padded_before"] = triple(padded_before);
  j["padded_after"] = triple(padded_after);
  const Json out = output.to_json();
  j["output_c1"] = out.at("c1");
  j["output_c2"] = out.at("c2");
  j["labels_left"] = out.at("labels_left");
  j["lost"] = lost;
  j["well_composed"] = output.total() == 0;
  return j;
}

std::string PartitionResult::failed_guarantee() const {
  std::string s;
  if (output.total()) {
    s = "output is NOT a well-composed partition (" + std::to_string(output.total()) +
        " critical configurations left, in " + std::to_string(output.labels_with_configurations()) + " labels)";
  }
  if (!lost_protected.empty()) {
    if (!s.empty()) s += "; ";
    s += "label " + std::to_string(lost_protected.front()) + " lost";
    if (lost_protected.size() > 1) s += " (and " + std::to_string(lost_protected.size() - 1) + " more)";
  }
  return s;
}

} // namespace imgmesh
