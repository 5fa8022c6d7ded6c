#!/usr/bin/env bash
# tri2quad end to end on hand-made constrained meshes and a random one made
# here from a fixed seed (the real images through img2poly and poly2tri are
# in pipeline2d.sh): quads checked by quad_check.py (strictly convex, edge to
# edge, area and region areas kept), constraints and markers by the segment
# check below, the size bounds counted from the files; every output format,
# stdout against the file output, and bad input (dangling constraint edge,
# truncated file, usage errors).
source "$(dirname "$0")/lib.sh"
QC=$E2E/quad_check.py

# The square with an interior constraint loop (a diamond around the centre),
# 1-based ids like Triangle's: 12 triangles, 2 constraint-bounded components.
square() {
cat > sq.node <<'N'
9 2 0 0
1 0 0
2 4 0
3 4 4
4 0 4
5 2 1
6 3 2
7 2 3
8 1 2
9 2 2
N
cat > sq.ele <<'N'
12 3 1
1 1 2 5 1
2 2 6 5 1
3 2 3 6 1
4 3 7 6 1
5 3 4 7 1
6 4 8 7 1
7 4 1 8 1
8 1 5 8 1
9 5 6 9 2
10 6 7 9 2
11 7 8 9 2
12 8 5 9 2
N
cat > sq.poly <<'N'
0 2 0 1
8 1
1 1 2 1
2 2 3 1
3 3 4 1
4 4 1 1
5 5 6 2
6 6 7 2
7 7 8 2
8 8 5 2
0
N
}

# segments_kept IN OUT [MARKERS]: for each marker, every output segment lies
# on an input segment of that marker and their lengths add up to the
# input's; the markers are MARKERS ("1 2" by default) in both.
segments_kept() {
  python3 - "$1.node" "$1.poly" "$2.node" "$2.poly" "${3:-1 2}" <<'PY' > seg.txt 2>&1 || fail "$2.poly: constraint segments or markers lost: $(cat seg.txt)"
import math, sys
def rows(path):
    return [l.split('#', 1)[0].split() for l in open(path) if l.split('#', 1)[0].split()]
def segments(node, poly):
    N = rows(node); pts = {r[0]: (float(r[1]), float(r[2])) for r in N[1:1 + int(N[0][0])]}
    P = rows(poly); k = 1 + int(P[0][0]); ns = int(P[k][0])
    return [(pts[r[1]], pts[r[2]], int(r[3])) for r in P[k + 1:k + 1 + ns]]
def on(p, a, b):  # p on the closed segment ab
    ux, uy, vx, vy = b[0] - a[0], b[1] - a[1], p[0] - a[0], p[1] - a[1]
    l2 = ux * ux + uy * uy; t = (ux * vx + uy * vy) / l2
    return abs(ux * vy - uy * vx) <= 1e-9 * l2 and -1e-9 <= t <= 1 + 1e-9
inp, out = segments(*sys.argv[1:3]), segments(*sys.argv[3:5])
bad = []
for m in sorted({s[2] for s in inp}):
    I = [s for s in inp if s[2] == m]; O = [s for s in out if s[2] == m]
    off = sum(1 for a, b, _ in O if not any(on(a, c, d) and on(b, c, d) for c, d, _ in I))
    if off: bad.append('marker %d: %d of %d segments off its input segments' % (m, off, len(O)))
    lo, li = sum(math.dist(a, b) for a, b, _ in O), sum(math.dist(a, b) for a, b, _ in I)
    if abs(lo - li) >= 1e-9: bad.append('marker %d: length %.9g, input %.9g' % (m, lo, li))
if not {s[2] for s in out} == {s[2] for s in inp} == set(map(int, sys.argv[5].split())):
    bad.append('markers %s, input %s' % (sorted({s[2] for s in out}), sorted({s[2] for s in inp})))
sys.exit('; '.join(bad) if bad else 0)
PY
}

# bounds IN OUT T H [--allow-outside]: at most floor(3T/2) + 4H quads and
# T + 7H Steiner points (T + 3H with --allow-outside), from the files.
bounds() {
  local q s k=7
  [[ -n ${5:-} ]] && k=3
  q=$(count "$2.ele"); s=$(( $(count "$2.node") - $(count "$1.node") ))
  local sb=$(( $3 + k * $4 ))
  (( q <= 3 * $3 / 2 + 4 * $4 && s <= sb && s >= 0 )) || fail "$2: $q quads, $s Steiner points for t = $3, h = $4"
}

case_constrained_square_keeps_constraints_regions_area() {
  square
  expect 0 tri2quad sq.ele sq.q.ele
  python3 "$QC" sq.q.ele sq.ele --fixed > qc.txt 2>&1 || fail "$(cat qc.txt)"
  segments_kept sq sq.q
  bounds sq sq.q 12 2
  expect 0 tri2quad sq.ele sq.o.ele --allow-outside
  python3 "$QC" sq.o.ele sq.ele --fixed > qc.txt 2>&1 || fail "--allow-outside: $(cat qc.txt)"
  segments_kept sq sq.o
  bounds sq sq.o 12 2 --allow-outside
}

# A jittered 20 x 20 grid split along random diagonals (python's Random(7)),
# no constraints but the boundary: one component.
case_random_triangulation_within_bounds() {
  python3 - <<'PY'
import random
r, n = random.Random(7), 20
m = n + 1
with open('g.node', 'w') as f:
    print(m * m, 2, 0, 1, file=f)
    for j in range(m):
        for i in range(m):
            b = i in (0, n) or j in (0, n)
            x, y = (i, j) if b else (i + 0.6 * (r.random() - 0.5), j + 0.6 * (r.random() - 0.5))
            print(j * m + i, repr(x), repr(y), int(b), file=f)
with open('g.ele', 'w') as f:
    print(2 * n * n, 3, 0, file=f)
    k = 0
    for j in range(n):
        for i in range(n):
            a = i + m * j; b, c, d = a + 1, a + m + 1, a + m
            for t in ((a, b, c), (a, c, d)) if r.random() < 0.5 else ((a, b, d), (b, c, d)):
                print(k, *t, file=f); k += 1
PY
  for pa in 0 40; do
    expect 0 tri2quad g.ele g$pa.q.ele --pair-above $pa
    python3 "$QC" g$pa.q.ele g.ele --fixed > qc.txt 2>&1 || fail "--pair-above $pa: $(cat qc.txt)"
    bounds g g$pa.q 800 1
  done
}

# Triangulations made by someone else: Gmsh's (Debian's gmsh, its default
# frontal-Delaunay) of a plate with three holes and of a square with a
# curved inclusion (two regions, their interface a constraint), each at two
# sizes. tri2quad then quadsmooth, with no option: strictly convex, edge to
# edge, each region's area, every boundary and constraint vertex kept
# (--fixed) and every segment kept, within the size bounds; mean mu >= 30
# and min mu >= 10 (the domains have no input angle under 90 degrees).
case_gmsh_triangulations_quads_mean_mu_30_min_10() {
  command -v gmsh > /dev/null || die "gmsh is not installed (scripts/install-deps installs it)"
  local geo size name markers h
  for geo in holes inclusion; do
    cp "$E2E/$geo.geo" .
    for size in 0.4 0.2; do
      name=$geo$size
      expect 0 gmsh -v 0 "$geo.geo" -2 -format msh22 -clmax "$size" -o "$name.msh" &&
        expect 0 python3 "$E2E/gmsh_triangles.py" "$name.msh" "$name" &&
        expect 0 tri2quad "$name.ele" "$name.q.ele" &&
        expect 0 quadsmooth "$name.q.ele" "$name.qs.ele" || continue
      markers="1 2" h=2
      [[ $geo == holes ]] && markers=1 h=1
      python3 "$QC" "$name.qs.ele" "$name.ele" --fixed > qc.txt 2>&1 || fail "$name: $(cat qc.txt)"
      segments_kept "$name" "$name.qs" "$markers"
      bounds "$name" "$name.q" "$(count "$name.ele")" "$h"
      "$BIN/meshinfo" --json "$name.qs.ele" > mi.json
      python3 -c "import sys; mean, mn = map(float, sys.argv[1:]); sys.exit(not (mean >= 30 and mn >= 10))" \
        "$(json mi.json quad_quality.mean_mu)" "$(json mi.json quad_quality.min_mu)" ||
        fail "$name ($(count "$name.ele") triangles): mean mu $(json mi.json quad_quality.mean_mu)," \
             "min mu $(json mi.json quad_quality.min_mu)"
    done
  done
}

case_formats_off_vtk_msh_svg_hold_the_quads() {
  square
  expect 0 tri2quad sq.ele ref.ele
  local q; q=$(count ref.ele)
  for ext in off vtk msh svg; do expect 0 tri2quad sq.ele "sq.q.$ext" --ascii; done
  [[ $(sed -n 2p sq.q.off | cut -d' ' -f2) == "$q" && $(tail -n "$q" sq.q.off | grep -c '^4 ') == "$q" ]] || fail ".off: not $q quads"
  grep -q "^CELLS $q " sq.q.vtk || fail ".vtk: not $q cells"
  grep -q '^\$MeshFormat' sq.q.msh && [[ $(awk '/^\$Elements/ { e = 1; getline; next } /^\$EndElements/ { e = 0 } e && $2 == 3' sq.q.msh | wc -l) == "$q" ]] ||
    fail ".msh: not $q elements"
  [[ $(grep -c '<polygon' sq.q.svg) == "$q" ]] || fail ".svg: not $q polygons"
  for f in sq.q.vtk sq.q.msh sq.q.svg; do whole "$f"; done
}

case_stdin_stdout_are_the_files() {
  square
  OUT=stdout.off expect 0 tri2quad sq.ele -
  expect 0 tri2quad sq.ele file.off
  cmp -s stdout.off file.off || fail "OUT - differs from OUT file.off"
  printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' > one.off
  IN=one.off OUT=one-stdout.off expect 0 tri2quad - -
  expect 0 tri2quad one.off one-file.off
  cmp -s one-stdout.off one-file.off || fail "IN - differs from IN one.off"
  [[ $(sed -n 2p one-file.off | cut -d' ' -f2) == 5 ]] || fail "one triangle: expected Joe's 5 quads"
  IN=file.off expect 1 tri2quad - x.off
}

case_dangling_constraint_refused_naming_the_edge() {
cat > bad.node <<'N'
5 2 0 0
1 0 0
2 2 0
3 2 2
4 0 2
5 1 1
N
cat > bad.ele <<'N'
4 3 0
1 1 2 5
2 2 3 5
3 3 4 5
4 4 1 5
N
  printf '0 2 0 1\n1 1\n1 1 5 1\n0\n' > bad.poly
  for pa in 0 40; do  # pairs first refuses it the same way (its pairs would hide it)
    expect 1 tri2quad bad.ele bad.q.ele --pair-above $pa
    grep -Eq '\((1, 5|5, 1)\)' err.txt || fail "dangling edge not named: $(cat err.txt)"
    [[ $(wc -l < err.txt) == 1 ]] || fail "error is not one line"
    [[ ! -e bad.q.ele ]] || fail "output written on error"
  done
  # A dangling constraint between triangles that pairs first would merge
  # (every lattice square across its diagonal): still refused.
  printf '9 2 0 0\n1 0 0\n2 1 0\n3 2 0\n4 0 1\n5 1 1\n6 2 1\n7 0 2\n8 1 2\n9 2 2\n' > bad2.node
  printf '8 3 0\n1 1 2 5\n2 1 5 4\n3 2 3 6\n4 2 6 5\n5 4 5 8\n6 4 8 7\n7 5 6 9\n8 5 9 8\n' > bad2.ele
  printf '0 2 0 1\n1 1\n1 2 5 1\n0\n' > bad2.poly
  expect 1 tri2quad bad2.ele bad2.q.ele --pair-above 40
  grep -Eq '\((2, 5|5, 2)\)' err.txt || fail "dangling edge not named: $(cat err.txt)"
  [[ ! -e bad2.q.ele ]] || fail "output written on error"
}

case_bad_input_exit_1_2_without_output() {
  square
  expect 0 tri2quad sq.ele sq.q.ele
  head -3 sq.ele > trunc.ele; cp sq.node trunc.node
  expect 1 tri2quad trunc.ele trunc.q.ele
  expect 1 tri2quad nothere.ele x.ele
  expect 2 tri2quad sq.ele x.txt
  expect 2 tri2quad sq.ele x.ele --bogus
  expect 1 tri2quad sq.q.ele x.ele
  [[ -z $(ls | grep -v -e '^sq\.' -e '^trunc\.' -e '^err.txt$' -e '^out.txt$') ]] || fail "left: $(ls)"
}

# Exit 3: a dart (two triangles whose union is not convex) taken as one
# quad without the convexity test (the hidden test-only
# --skip-convexity-test): the final check must find it, exit 3, the mesh
# written (file and stdout alike), and quad_check.py rejects it too.
case_exit_3_when_the_convexity_test_is_skipped() {
  printf '4 2 0 1\n0 0 0 1\n1 3 1 1\n2 0 2 1\n3 1 1 0\n' > d.node
  printf '2 3 0\n0 0 1 3\n1 3 1 2\n' > d.ele
  expect 0 tri2quad d.ele ok.q.ele
  python3 "$QC" ok.q.ele d.ele --fixed > qc.txt 2>&1 || fail "the dart without the skip: $(cat qc.txt)"
  expect 3 tri2quad d.ele d.q.ele --skip-convexity-test
  grep -q "^tri2quad: guarantee not met: 1 quads not strictly convex" err.txt || fail "no guarantee message: $(cat err.txt)"
  [[ $(count d.q.ele) == 1 ]] || fail "$(count d.q.ele) quads, want the dart alone"
  python3 "$QC" d.q.ele d.ele --fixed > qc.txt 2>&1 && fail "quad_check.py accepts the dart"
  expect 3 tri2quad d.ele d.off --skip-convexity-test
  OUT=d-stdout.off expect 3 tri2quad d.ele - --skip-convexity-test
  cmp -s d-stdout.off d.off || fail "OUT - differs from OUT d.off on exit 3"
}

run_cases "$@"
