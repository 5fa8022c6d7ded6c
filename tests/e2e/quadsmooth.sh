#!/usr/bin/env bash
# quadsmooth end to end on jittered quad grids made here from fixed seeds (no
# other tool upstream: the real images through the whole 2D chain are in
# pipeline2d.sh). Each output is checked by quad_check.py (strictly convex,
# edge to edge, area and region areas kept, boundary fixed or on its sides)
# and meshinfo (topology, Joe's mu); plus thread-count independence, formats,
# stdout against the file output, a non-convex input (exit 3) and bad input.
source "$(dirname "$0")/lib.sh"
QC=$E2E/quad_check.py

# grid N SEED JITTER NAME: an N x N quad grid of the square [0, N]^2, inner
# nodes jittered by up to JITTER/2, boundary nodes marked 1, left half
# region 1, right half region 2.
grid() {
  python3 - "$@" <<'PY'
import random, sys
n, seed, jit, name = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
r, m = random.Random(seed), n + 1
with open(name + '.node', 'w') as f:
    print(m * m, 2, 0, 1, file=f)
    for j in range(m):
        for i in range(m):
            b = i in (0, n) or j in (0, n)
            x, y = (i, j) if b else (i + jit * (r.random() - 0.5), j + jit * (r.random() - 0.5))
            print(j * m + i, repr(x), repr(y), int(b), file=f)
with open(name + '.ele', 'w') as f:
    print(n * n, 4, 1, file=f)
    for j in range(n):
        for i in range(n):
            a = i + m * j
            print(j * n + i, a, a + 1, a + m + 1, a + m, 1 if i < n // 2 else 2, file=f)
PY
}
small() { grid 24 6 0.6 in; }
IN_ELE() { local d; d=$(dirname "$(shared in.ele small)"); cp "$d/in.ele" "$d/in.node" .; }
# mu MESH KEY: a meshinfo --json entry, meshinfo run once a mesh.
mu() { [[ -s $1.json ]] || "$BIN/meshinfo" --json "$1" > "$1.json"; json "$1.json" "$2"; }

case_smoothing_keeps_quads_convex_boundary_regions() {
  IN_ELE
  expect 0 quadsmooth in.ele out.ele --svg out.svg
  python3 "$QC" out.ele in.ele --fixed > qc.txt 2>&1 || fail "$(cat qc.txt)"
  # meshinfo reads the files: same topology, worst mu not lower, mean higher.
  [[ $(mu in.ele components) == 1 && $(mu out.ele components) == 1 && $(mu out.ele euler) == "[1]" ]] ||
    fail "topology changed: $(mu out.ele components) components, euler $(mu out.ele euler)"
  [[ $(mu out.ele quad_quality.non_convex) == 0 ]] || fail "meshinfo sees non-convex quads"
  python3 -c "import sys; b, a, mb, ma = map(float, sys.argv[1:]); sys.exit(not (a >= b - 1e-9 and ma > mb + 1))" \
    "$(mu in.ele quad_quality.min_mu)" "$(mu out.ele quad_quality.min_mu)" "$(mu in.ele quad_quality.mean_mu)" "$(mu out.ele quad_quality.mean_mu)" ||
    fail "mu min $(mu in.ele quad_quality.min_mu) -> $(mu out.ele quad_quality.min_mu), mean $(mu in.ele quad_quality.mean_mu) -> $(mu out.ele quad_quality.mean_mu)"
  [[ $(grep -c '<polygon' out.svg) == $(count out.ele) ]] || fail "the SVG does not draw every quad"
}

# split N SEED NAME: a jittered N x N square split along random diagonals,
# each triangle cut into three quads at its centroid and edge midpoints
# (valence 3 at the centroids, 6 at the grid's inner points: the clean-up
# swaps and collapses there, where the jittered grid gives it nothing to do).
split() {
  python3 - "$@" <<'PY'
import random, sys
n, seed, name = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
r, m = random.Random(seed), n + 1
P, B = [], []
for j in range(m):
    for i in range(m):
        b = i in (0, n) or j in (0, n)
        P.append((i, j) if b else (i + 0.5 * (r.random() - 0.5), j + 0.5 * (r.random() - 0.5))); B.append(int(b))
tris = []
for j in range(n):
    for i in range(n):
        a = i + m * j; b, c, d = a + 1, a + m + 1, a + m
        tris += [(a, b, c), (a, c, d)] if r.random() < 0.5 else [(a, b, d), (b, c, d)]
mid = {}
def midpoint(u, v):
    k = (min(u, v), max(u, v))
    if k not in mid:
        mid[k] = len(P)
        P.append(((P[u][0] + P[v][0]) / 2, (P[u][1] + P[v][1]) / 2))
        B.append(int(B[u] and B[v] and (P[u][0] == P[v][0] or P[u][1] == P[v][1])))
    return mid[k]
quads = []
for a, b, c in tris:
    g = len(P); P.append(((P[a][0] + P[b][0] + P[c][0]) / 3, (P[a][1] + P[b][1] + P[c][1]) / 3)); B.append(0)
    ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
    reg = 1 if P[g][0] < n / 2 else 2
    quads += [(a, ab, g, ca, reg), (b, bc, g, ab, reg), (c, ca, g, bc, reg)]
with open(name + '.node', 'w') as f:
    print(len(P), 2, 0, 1, file=f)
    for k, (p, b) in enumerate(zip(P, B)): print(k, repr(p[0]), repr(p[1]), b, file=f)
with open(name + '.ele', 'w') as f:
    print(len(quads), 4, 1, file=f)
    for k, q in enumerate(quads): print(k, *q, file=f)
PY
}

# On a mesh the clean-up changes, --no-cleanup only moves nodes.
case_no_cleanup_keeps_the_quads() {
  split 8 6 in
  elements() { grep -v '^ *#' "$1" | tail -n +2 | awk 'NF { $1 = ""; print }'; }
  expect 0 quadsmooth in.ele clean.ele
  [[ $(elements in.ele) != "$(elements clean.ele)" ]] || fail "the clean-up did nothing here: the case cannot see --no-cleanup"
  expect 0 quadsmooth in.ele nc.ele --no-cleanup
  python3 "$QC" nc.ele in.ele --fixed > qc.txt 2>&1 || fail "$(cat qc.txt)"
  # Only moves: the same quads on the same nodes, in the same order.
  [[ $(elements in.ele) == "$(elements nc.ele)" ]] || fail "--no-cleanup changed the elements"
}

case_slide_boundary_stays_on_the_sides() {
  IN_ELE
  expect 0 quadsmooth in.ele sl.ele --slide-boundary --iterations 5
  python3 "$QC" sl.ele in.ele --on-sides 24 > qc.txt 2>&1 || fail "$(cat qc.txt)"
}

# A colour group under 4,096 vertices runs on one thread, so the grid is
# 150 x 150 quads: the greedy colouring of its 149^2 inner vertices gives 4
# groups of ~5,500.
case_threads_do_not_change_the_output() {
  grid 150 8 0.6 big
  expect 0 quadsmooth big.ele t1.ele --threads 1 --iterations 3
  expect 0 quadsmooth big.ele t2.ele --threads 2 --iterations 3
  cmp -s t1.node t2.node && cmp -s t1.ele t2.ele || fail "--threads 1 and 2 differ"
  # Enough moved for the two threads to have had work.
  moved=$(paste <(tail -n +2 big.node) <(grep -v '^ *#' t2.node | tail -n +2) | awk '$2 + 0 != $6 + 0 || $3 + 0 != $7 + 0' | wc -l)
  [[ $moved -gt 10000 ]] || fail "the thread-count case hardly moved: $moved nodes"
}

case_formats_off_vtk_msh_hold_the_mesh() {
  IN_ELE
  expect 0 quadsmooth in.ele ref.ele --iterations 2
  local q; q=$(count ref.ele)
  for ext in off vtk msh; do expect 0 quadsmooth in.ele "out.$ext" --iterations 2 --ascii; done
  [[ $(sed -n 2p out.off | cut -d' ' -f2) == "$q" && $(tail -n "$q" out.off | grep -c '^4 ') == "$q" ]] || fail ".off: not $q quads"
  grep -q "^CELLS $q " out.vtk || fail ".vtk: not $q cells"
  grep -q '^\$MeshFormat' out.msh && [[ $(awk '/^\$Elements/ { e = 1; getline; next } /^\$EndElements/ { e = 0 } e && $2 == 3' out.msh | wc -l) == "$q" ]] ||
    fail ".msh: not $q elements"
  for f in out.vtk out.msh; do whole "$f"; done
  # The OFF reads back as input.
  expect 0 quadsmooth out.off again.ele --iterations 1
  python3 "$QC" again.ele > qc.txt 2>&1 || fail "OFF input: $(cat qc.txt)"
}

case_stdout_is_the_off_file() {
  IN_ELE
  OUT=stdout.off expect 0 quadsmooth in.ele - --iterations 2
  expect 0 quadsmooth in.ele file.off --iterations 2
  cmp -s stdout.off file.off || fail "OUT - differs from OUT file.off"
  IN=file.off OUT=stdin.off expect 0 quadsmooth - - --iterations 1
  expect 0 quadsmooth file.off file2.off --iterations 1
  cmp -s stdin.off file2.off || fail "IN - differs from IN file.off"
}

# A quad that comes in non-convex (all corners fixed): the output is written,
# exit 3 with one line saying which guarantee failed, --stats says so too,
# and - gives the same bytes.
case_nonconvex_input_exit_3_with_output() {
  printf '4 2 0 0\n0 0 0\n1 2 0\n2 0.5 0.5\n3 0 2\n' > dart.node
  printf '1 4 0\n0 0 1 2 3\n' > dart.ele
  expect 3 quadsmooth dart.ele dart.q.ele --stats dart.json
  [[ $(grep -c 'guarantee not met: 1 quad(s) are not strictly convex (they came in that way)' err.txt) == 1 ]] ||
    fail "non-convex output not named: $(cat err.txt)"
  [[ $(count dart.q.ele) == 1 ]] || fail "non-convex output not written"
  [[ $(json dart.json exit_status) == 3 && $(json dart.json guarantees.strictly_convex) == False ]] || fail "--stats of a non-convex output"
  [[ $(grep -c 'seconds' dart.json) == 1 ]] || fail "more than one time in --stats"
  expect 3 quadsmooth dart.ele dart.off
  OUT=dart-stdout.off expect 3 quadsmooth dart.ele -
  cmp -s dart.off dart-stdout.off || fail "exit 3: OUT - differs from the file output"
}

case_bad_input_exit_1_2_without_output() {
  IN_ELE
  head -4 in.ele > trunc.ele; cp in.node trunc.node
  expect 1 quadsmooth trunc.ele t.ele
  [[ $(wc -l < err.txt) == 1 ]] || fail "error is not one line"
  printf '4 2 0 0\n0 0 0\n1 1 0\n2 1 1\n3 0 1\n' > cw.node
  printf '1 4 0\n0 0 3 2 1\n' > cw.ele
  expect 1 quadsmooth cw.ele c.ele
  grep -q clockwise err.txt || fail "clockwise not named: $(cat err.txt)"
  expect 1 quadsmooth nothere.ele x.ele
  expect 2 quadsmooth in.ele x.ele --iterations -1
  expect 2 quadsmooth in.ele
  expect 2 quadsmooth in.ele x.ele --bogus
  local g
  for g in nan inf -1 0.5; do expect 2 quadsmooth in.ele x.ele --grading "$g"; done
  [[ -z $(ls | grep -v -e '^in\.' -e '^trunc\.' -e '^cw\.' -e '^err.txt$' -e '^out.txt$') ]] || fail "left: $(ls)"
}

run_cases "$@"
