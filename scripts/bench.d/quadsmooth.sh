#!/usr/bin/env bash
# quadsmooth: (1) speed: 10^6 quads (jittered 1000 x 1000 grid), 10 passes,
# the tool's time from --stats (seconds: read, smooth, write), wall and CPU,
# on 1 thread and on all cores; (2) quality: tri2quad + quadsmooth on a
# jittered-grid Delaunay-like mesh of 2048 triangles and on 20000 triangles,
# and on the real images of share/data through img2poly and poly2tri (the
# README's default chain, and the thesis's), side by side with Gmsh's Blossom
# recombination of the very same triangles and Gmsh's own pipeline; (3) given
# triangulations: Gmsh's own of a plate with holes and of a two-region
# square, through tri2quad and quadsmooth, beside Blossom on the same
# triangles and Gmsh's own pipeline: min, median, mean mu, min scaled
# Jacobian, share of quads with angles in [45, 135].   $1: tool folder.
set -euo pipefail
BIN=${1:?usage: quadsmooth.sh TOOL_FOLDER}
DATA=$(cd "$(dirname "$0")/../../share/data" && pwd)
E2E=$(cd "$(dirname "$0")/../../tests/e2e" && pwd)  # before the cd below: $0 may be relative
work=$(mktemp -d "${TMPDIR:-/tmp}/quadsmooth-bench.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"
stat() { sed -n "s/^ *\"$1\": *\([^,]*\),*$/\1/p" "$2"; }

if [ "${QUADSMOOTH_BENCH_SPEED:-1}" = 1 ]; then
echo "speed: 10^6 quads, 10 passes"
python3 - <<'PY'
import random
n = 1000; m = n + 1; r = random.Random(1)
with open("big.node", "w") as f:
    f.write("%d 2 0 1\n" % (m * m))
    out = []
    for j in range(m):
        for i in range(m):
            b = i in (0, n) or j in (0, n)
            x = i + (0 if b else r.uniform(-0.25, 0.25)); y = j + (0 if b else r.uniform(-0.25, 0.25))
            out.append("%d %.10g %.10g %d\n" % (j * m + i, x, y, b))
    f.writelines(out)
with open("big.ele", "w") as f:
    f.write("%d 4 0\n" % (n * n))
    f.writelines("%d %d %d %d %d\n" % (j * n + i, j * m + i, j * m + i + 1, j * m + i + m + 1, j * m + i + m)
                 for j in range(n) for i in range(n))
PY
for threads in 1 $(nproc); do
  /usr/bin/time -f "%e %U %S %M" -o time.txt "$BIN/quadsmooth" -q big.ele big.s.ele --iterations 10 --threads "$threads" --stats big.json
  read -r wall user sys kb < time.txt
  mins=($(stat min_mu big.json)); means=($(stat mean_mu big.json))
  echo "  $threads thread(s): $(stat seconds big.json) s in the tool (read, smooth, write);" \
       "whole run $wall s wall," \
       "$(echo "$user + $sys" | bc) s CPU, peak $((kb / 1024)) MB; min mu ${mins[0]} -> ${mins[1]}, mean mu ${means[0]} -> ${means[1]}"
done
fi

# grid N SEED: jittered N x N grid cut along random diagonals (2 N^2 triangles)
# as g.node/g.ele and g.msh (Gmsh 2.2).
grid() {
  python3 - "$1" "$2" <<'PY'
import random, sys
n = int(sys.argv[1]); r = random.Random(int(sys.argv[2])); m = n + 1
P = []
for j in range(m):
    for i in range(m):
        P.append((i + (0 if i in (0, n) else r.uniform(-0.3, 0.3)), j + (0 if j in (0, n) else r.uniform(-0.3, 0.3))))
T = []
for j in range(n):
    for i in range(n):
        a, b, c, d = i + m * j, i + 1 + m * j, i + 1 + m * (j + 1), i + m * (j + 1)
        T += [(a, b, c), (a, c, d)] if r.random() < 0.5 else [(a, b, d), (b, c, d)]
with open("g.node", "w") as f:
    f.write("%d 2 0 0\n" % len(P)); f.writelines("%d %.12g %.12g\n" % (k, x, y) for k, (x, y) in enumerate(P))
with open("g.ele", "w") as f:
    f.write("%d 3 0\n" % len(T)); f.writelines("%d %d %d %d\n" % (k, *t) for k, t in enumerate(T))
with open("g.msh", "w") as f:
    f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(P))
    f.writelines("%d %.12g %.12g 0\n" % (k + 1, x, y) for k, (x, y) in enumerate(P))
    f.write("$EndNodes\n$Elements\n%d\n" % len(T))
    f.writelines("%d 2 2 1 1 %d %d %d\n" % (k + 1, t[0] + 1, t[1] + 1, t[2] + 1) for k, t in enumerate(T))
    f.write("$EndElements\n")
PY
}

# Quality figures of a quad mesh given as .msh (Gmsh 2.2): one line.
msh_quality() {
  python3 - "$1" "$2" <<'PY'
import math, sys
text = open(sys.argv[1]).read()
L = text.split("$Nodes")[1].split("\n"); n = int(L[1]); P = {}
for l in L[2:2 + n]:
    k, x, y, z = l.split(); P[int(k)] = (float(x), float(y))
E = text.split("$Elements")[1].split("\n"); ne = int(E[1])
def ang(a, b, c):
    ux, uy = b[0] - a[0], b[1] - a[1]; vx, vy = c[0] - a[0], c[1] - a[1]
    return math.degrees(math.atan2(abs(ux * vy - uy * vx), ux * vx + uy * vy))
def tmin(a, b, c): return min(ang(a, b, c), ang(b, c, a), ang(c, a, b))
mus, sjs, good, tris = [], [], 0, 0
for l in E[2:2 + ne]:
    f = l.split(); t = int(f[1]); nt = int(f[2]); v = [P[int(x)] for x in f[3 + nt:]]
    if t == 2: tris += 1
    if t != 3: continue
    if sum(v[i][0] * v[(i + 1) % 4][1] - v[i][1] * v[(i + 1) % 4][0] for i in range(4)) < 0:
        v = v[::-1]  # Gmsh may write quads clockwise
    a, b, c, d = v
    mus.append(min(tmin(a, b, d), tmin(c, d, b), tmin(a, b, c), tmin(d, a, c)))
    sj, ok = 1, True
    for i in range(4):
        o, nx, pr = v[i], v[(i + 1) % 4], v[(i + 3) % 4]
        ux, uy = nx[0] - o[0], nx[1] - o[1]; vx, vy = pr[0] - o[0], pr[1] - o[1]
        cr = ux * vy - uy * vx
        sj = min(sj, cr / math.hypot(ux, uy) / math.hypot(vx, vy))
        an = ang(o, nx, pr)
        if cr < 0: an = 360 - an
        ok = ok and 45 <= an <= 135
    sjs.append(sj); good += ok
mus.sort()
print("  %-22s quads=%6d tris left=%4d  mu min %5.2f median %5.2f mean %5.2f  min SJ %.3f  angles in [45,135] %5.1f%%" %
      (sys.argv[2], len(mus), tris, mus[0], mus[len(mus) // 2], sum(mus) / len(mus), min(sjs), 100.0 * good / len(mus)))
PY
}

# Gmsh's Blossom recombination of the triangles in $1 (Gmsh 2.2), one line.
blossom() {
  if command -v gmsh > /dev/null; then
    printf 'Merge "%s";\nMesh.RecombinationAlgorithm = 1;\nRecombineMesh;\nMesh.MshFileVersion = 2.2;\nSave "rec.msh";\n' "$1" > rec.geo
    if /usr/bin/time -f "%e" -o gt.txt timeout 600 gmsh -v 0 rec.geo -0 > /dev/null 2>&1 && [ -s rec.msh ]; then
      msh_quality rec.msh "gmsh blossom"
      echo "  (gmsh $(cat gt.txt) s wall)"
    else
      echo "  gmsh blossom: failed"
    fi
  else
    echo "  gmsh: not installed (apt-get install gmsh)"
  fi
}

# Gmsh's own pipeline on the segments of poly2tri's mesh $1.{node,ele,poly}:
# one Gmsh line per subsegment, one plane surface per region component (its
# boundary loops, outer first), frontal-Delaunay triangles (Mesh.Algorithm 6;
# 8, frontal-Delaunay for quads, crashes Gmsh 4.8.4 on these inputs)
# recombined with Blossom, Gmsh's own sizes. One line.
gmsh_own() {
  command -v gmsh > /dev/null || return 0
  python3 - "$1" own.geo <<'PY'
import collections, sys
base, out = sys.argv[1], sys.argv[2]
def rows(f): return [l.split() for l in open(f) if l.strip() and not l.lstrip().startswith('#')]
N = rows(base + ".node"); first = int(N[1][0])
P = [(float(r[1]), float(r[2])) for r in N[1:1 + int(N[0][0])]]
E = rows(base + ".ele"); T = [[int(x) - first for x in r[1:4]] for r in E[1:1 + int(E[0][0])]]
S = rows(base + ".poly"); seg = {tuple(sorted((int(r[1]) - first, int(r[2]) - first))) for r in S[2:2 + int(S[1][0])]}
tris = collections.defaultdict(list)
for i, t in enumerate(T):
    for j in range(3): tris[tuple(sorted((t[j], t[j - 2])))].append(i)
line = {e: k + 1 for k, e in enumerate(e for e, ts in tris.items() if e in seg or len(ts) == 1)}
comp, c = [-1] * len(T), 0
for s in range(len(T)):  # regions: components across non-segment edges
    if comp[s] >= 0: continue
    comp[s], stack = c, [s]
    while stack:
        i = stack.pop()
        for j in range(3):
            e = tuple(sorted((T[i][j], T[i][j - 2])))
            for o in ([] if e in line else tris[e]):
                if comp[o] < 0: comp[o] = c; stack.append(o)
    c += 1
g = open(out, "w")
for v in sorted({v for e in line for v in e}): g.write("Point(%d) = {%.12g, %.12g, 0};\n" % (v + 1, *P[v]))
for (a, b), k in line.items(): g.write("Line(%d) = {%d, %d};\n" % (k, a + 1, b + 1))
nxt = [collections.defaultdict(list) for _ in range(c)]
for i, t in enumerate(T):  # boundary edges, counter-clockwise around their region
    for j in range(3):
        if tuple(sorted((t[j - 1], t[j]))) in line: nxt[comp[i]][t[j - 1]].append(t[j])
loops = 0
for k in range(c):
    ls = []
    while nxt[k]:
        a0 = a = next(iter(nxt[k])); L, area = [], 0
        while True:
            b = nxt[k][a].pop()
            if not nxt[k][a]: del nxt[k][a]
            L.append(line[(a, b)] if a < b else -line[(b, a)]); area += P[a][0] * P[b][1] - P[b][0] * P[a][1]; a = b
            if a == a0: break
        ls.append((-area, L))
    ids = []
    for _, L in sorted(ls):
        loops += 1; ids.append(loops); g.write("Curve Loop(%d) = {%s};\n" % (loops, ", ".join(map(str, L))))
    g.write("Plane Surface(%d) = {%s};\n" % (k + 1, ", ".join(map(str, ids))))
g.write('Mesh.Algorithm = 6;\nMesh.RecombineAll = 1;\nMesh.RecombinationAlgorithm = 1;\n'
        'Mesh.MshFileVersion = 2.2;\nMesh 2;\nSave "own.msh";\n')
PY
  rm -f own.msh
  if /usr/bin/time -f "%e" -o gt.txt timeout 600 gmsh -v 0 own.geo -0 > /dev/null 2>&1 && [ -s own.msh ]; then
    msh_quality own.msh "gmsh own pipeline"
    echo "  (gmsh $(cat gt.txt) s wall)"
  else
    echo "  gmsh own pipeline: failed"
  fi
}

for n in 32 100; do
  rm -f rec.msh
  grid "$n" 5
  echo "quality: jittered grid of $((2 * n * n)) triangles"
  if [ -x "$BIN/tri2quad" ]; then
    "$BIN/tri2quad" -q g.ele q.ele
    "$BIN/tri2quad" -q g.ele q.msh
    msh_quality q.msh "tri2quad"
    /usr/bin/time -f "%e" -o t.txt "$BIN/quadsmooth" -q q.ele qs.msh --stats qs.json
    msh_quality qs.msh "tri2quad+quadsmooth"
    echo "  (quadsmooth $(stat seconds qs.json) s in the tool, $(cat t.txt) s wall)"
  else
    echo "  tri2quad not built"
  fi
  blossom g.msh
done

# The 2D pipeline on real images: name, image, img2poly options.
for spec in "VentricleModel:VentricleModel.png:--threshold 128" "BinaryImage:BinaryImage.png:" \
            "BrainT1Slice:BrainT1Slice.png:--threshold 100" "RatLungSlice1:RatLungSlice1.mha:--threshold 100"; do
  IFS=: read -r name image opts <<< "$spec"
  rm -f rec.msh
  # shellcheck disable=SC2086
  "$BIN/img2poly" -q "$DATA/$image" r.poly $opts
  "$BIN/poly2tri" -q r.poly r.1.ele
  "$BIN/poly2tri" -q r.poly r.msh
  echo "quality: $name ($opts) through img2poly and poly2tri (defaults: graded square lattice), $(sed -n 's/^# \([0-9]*\) triangles.*/\1/p' r.1.ele) triangles"
  "$BIN/tri2quad" -q r.1.ele q.ele
  "$BIN/tri2quad" -q r.1.ele q.msh
  msh_quality q.msh "tri2quad"
  /usr/bin/time -f "%e" -o t.txt "$BIN/quadsmooth" -q q.ele qs.msh --stats qs.json
  msh_quality qs.msh "default chain"
  echo "  (quadsmooth $(stat seconds qs.json) s in the tool, $(cat t.txt) s wall;" \
       "$(stat pair_splits qs.json) pair splits, $(stat pair_splits_four qs.json) of them into four," \
       "$(stat edge_moves qs.json) edge moves)"
  blossom r.msh
  gmsh_own r.1
  # The thesis's chain: Delaunay refinement's own points, the BFS pairing alone.
  "$BIN/poly2tri" -q r.poly t.1.ele --square-lattice 0
  "$BIN/tri2quad" -q t.1.ele t.q.ele --pair-above 0
  "$BIN/quadsmooth" -q t.q.ele ts.msh
  msh_quality ts.msh "thesis chain"
  for side in ${QUADSMOOTH_BENCH_LATTICES:-4 2 1}; do
    "$BIN/poly2tri" -q r.poly l.1.ele --lattice "$side"
    "$BIN/tri2quad" -q l.1.ele l.q.ele --pair-above 0
    /usr/bin/time -f "%e" -o t.txt "$BIN/quadsmooth" -q l.q.ele ls.msh --stats ls.json
    msh_quality ls.msh "--lattice $side: +tri2quad+qs"
    echo "  ($(sed -n 's/^# \([0-9]*\) triangles.*/\1/p' l.1.ele) triangles; quadsmooth $(stat seconds ls.json) s in the tool, $(cat t.txt) s wall)"
    # The quad chain: a square lattice, its squares merged first.
    "$BIN/poly2tri" -q r.poly l.1.ele --square-lattice "$side" --grading 0
    "$BIN/tri2quad" -q l.1.ele l.q.ele --pair-above 40 --stats lq.json
    /usr/bin/time -f "%e" -o t.txt "$BIN/quadsmooth" -q l.q.ele ls.msh --stats ls.json
    msh_quality ls.msh "--square-lattice $side --grading 0, --pair-above 40: +qs"
    echo "  ($(sed -n 's/^# \([0-9]*\) triangles.*/\1/p' l.1.ele) triangles, $(stat pairs_first lq.json) squares merged first;" \
         "quadsmooth $(stat seconds ls.json) s in the tool, $(cat t.txt) s wall)"
  done
done

# Given triangulations (Gmsh's own, frontal-Delaunay, of a plate with three
# holes and of a square with a curved inclusion, two regions): tri2quad and
# quadsmooth on them, beside Gmsh's Blossom recombination of the same
# triangles and Gmsh's own geometry-to-quads pipeline on the same geometry.
if command -v gmsh > /dev/null; then
  for geo in holes inclusion; do
    cp "$E2E/$geo.geo" .
    for size in 0.4 0.2; do
      gmsh -v 0 "$geo.geo" -2 -format msh22 -clmax "$size" -o gt.msh > /dev/null
      python3 "$E2E/gmsh_triangles.py" gt.msh gt
      echo "quality: Gmsh's triangulation of $geo.geo (-clmax $size), $(sed -n 's/^\([0-9]*\) 3 1$/\1/p' gt.ele) triangles"
      "$BIN/tri2quad" -q gt.ele gq.ele
      "$BIN/quadsmooth" -q gq.ele gqs.msh
      msh_quality gqs.msh "tri2quad+quadsmooth"
      "$BIN/tri2quad" -q gt.ele gq0.ele --pair-above 0
      "$BIN/quadsmooth" -q gq0.ele gqs0.msh --mean-rounds 0
      msh_quality gqs0.msh "(thesis: no pairs first, no mean pass)"
      rm -f rec.msh
      blossom gt.msh
      sed -e 's/^Physical.*//' "$geo.geo" > own.geo
      printf 'Mesh.RecombineAll = 1;\nMesh.RecombinationAlgorithm = 1;\nMesh.MeshSizeMax = %s;\nMesh.MshFileVersion = 2.2;\nMesh 2;\nSave "own.msh";\n' "$size" >> own.geo
      rm -f own.msh
      if timeout 600 gmsh -v 0 own.geo -0 > /dev/null 2>&1 && [ -s own.msh ]; then
        msh_quality own.msh "gmsh own pipeline"
      else
        echo "  gmsh own pipeline: failed"
      fi
    done
  done
fi
