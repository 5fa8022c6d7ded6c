#include "wellcomposed/critical_configuration.hpp"

namespace imgmesh::wellcomposed_detail {
namespace {

bool bit(unsigned code, int k) { return (code >> k) & 1u; }

// A 2x2 square with corners p00 p10 p01 p11 is (C1) when one diagonal is
// foreground and the other background (Definition 4.2.1).
bool square_c1(unsigned code, int p00, int p10, int p01, int p11) {
  return bit(code, p00) == bit(code, p11) && bit(code, p10) == bit(code, p01) &&
         bit(code, p00) != bit(code, p10);
}

// Two points of a 2x2x2 block are corner-adjacent when they differ in every
// coordinate: k ^ j == 7.
bool block_c2(unsigned code) {
  int ones = __builtin_popcount(code);
  unsigned minority = ones == 2 ? code : ones == 6 ? (~code & 0xffu) : 0u;
  if (!minority) return false;
  int k = __builtin_ctz(minority);
  return (minority & ~(1u << k)) == (1u << (k ^ 7));
}

struct Tables {
  std::array<std::uint8_t, 256> flags{};
  std::array<CandidateSets, 256> sets{};

  Tables() {
    for (unsigned code = 0; code < 256; ++code) {
      std::uint8_t f = 0;
      if (square_c1(code, 0, 2, 4, 6)) f |= kC1x;
      if (square_c1(code, 0, 1, 4, 5)) f |= kC1y;
      if (square_c1(code, 0, 1, 2, 3)) f |= kC1z;
      if (block_c2(code)) f |= kC2;
      flags[code] = f;
      sets[code] = build(code, f);
    }
  }

  static void add(CandidateSets& b, unsigned mask) { b.sets[b.count++] = std::uint8_t(mask); }

  static CandidateSets build(unsigned code, std::uint8_t f) {
    CandidateSets b;
    const unsigned bg = ~code & 0xffu;
    const unsigned square[3] = {0x55u /*N_x: 0,2,4,6*/, 0x33u /*N_y: 0,1,4,5*/, 0x0fu /*N_z: 0-3*/};
    unsigned c1[3], n = 0;
    for (int a = 0; a < 3; ++a)
      if (f & (1u << a)) c1[n++] = square[a];
    if (n == 1) {
      // One instance Y: B(r) = {{a}, {b}}, the two background points of Y.
      for (unsigned m = c1[0] & bg; m; m &= m - 1) add(b, m & -m);
    } else if (n == 2) {
      // Y1, Y2 share an edge of one foreground and one background point a:
      // B(r) = {{a}, {b, c}} with b, c the other background points (Fig. 5.6).
      const unsigned a = c1[0] & c1[1] & bg;
      add(b, a);
      add(b, ((c1[0] | c1[1]) & bg) & ~a);
    } else if (n == 3) {
      const unsigned all = (c1[0] | c1[1] | c1[2]) & bg;
      if (bg & 1u) {
        // The common point a = r is background: {{a}, {b, c, d}} (Fig. 5.7).
        add(b, 1u);
        add(b, all & ~1u);
      } else {
        // Three background points b, c, d: any two of them (Fig. 5.7).
        for (unsigned m = all; m; m &= m - 1) add(b, all & ~(m & -m));
      }
    } else if (f & kC2) {
      // Two or six background points: each alone (Figs. 5.4, 5.5).
      for (unsigned m = bg; m; m &= m - 1) add(b, m & -m);
    }
    return b;
  }
};

const Tables& tables() {
  static const Tables t;
  return t;
}

} // namespace

std::uint8_t critical_configurations(std::uint8_t code) { return tables().flags[code]; }
const CandidateSets& candidate_sets(std::uint8_t code) { return tables().sets[code]; }

} // namespace imgmesh::wellcomposed_detail
