#!/usr/bin/env bash
# tri2quad: time (the run's "seconds" from --stats, text I/O included), wall time,
# peak memory, quads/t and Steiner/t on jittered-grid triangle meshes of 10^4
# to 10^6 triangles (10^7 with TRI2QUAD_BENCH_BIG=1), and on a real mesh
# (RatLungSlice1 through img2poly and poly2tri). Side by side with Gmsh's
# Blossom recombination of the same triangles when gmsh is installed
# (Debian package gmsh): quads, triangles left, time, Joe's mu.   $1: tool folder.
set -euo pipefail
BIN=${1:?usage: tri2quad.sh TOOL_FOLDER}
DATA=$(cd "$(dirname "$0")/../../share/data" && pwd)
work=$(mktemp -d "${TMPDIR:-/tmp}/tri2quad-bench.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"

# grid N: an N x N jittered grid, each cell cut along a random diagonal
# (2 N^2 triangles), as grid.node/.ele and grid.msh (Gmsh 2.2).
grid() {
  python3 - "$1" <<'PY'
import random, sys
n = int(sys.argv[1]); r = random.Random(7); m = n + 1
with open("grid.node", "w") as f:
    f.write("%d 2 0 0\n" % (m * m))
    k = 0
    for j in range(m):
        for i in range(m):
            jx = 0 if i in (0, n) else r.uniform(-0.2, 0.2)
            jy = 0 if j in (0, n) else r.uniform(-0.2, 0.2)
            f.write("%d %.9g %.9g\n" % (k, i + jx, j + jy)); k += 1
tris = []
for j in range(n):
    for i in range(n):
        a, b, c, d = i + m * j, i + 1 + m * j, i + 1 + m * (j + 1), i + m * (j + 1)
        tris += [(a, b, c), (a, c, d)] if r.random() < 0.5 else [(a, b, d), (b, c, d)]
with open("grid.ele", "w") as f:
    f.write("%d 3 0\n" % len(tris))
    f.writelines("%d %d %d %d\n" % (k, t[0], t[1], t[2]) for k, t in enumerate(tris))
if n <= 320:
    with open("grid.msh", "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % (m * m))
        for line in open("grid.node").readlines()[1:]:
            k, x, y = line.split(); f.write("%d %s %s 0\n" % (int(k) + 1, x, y))
        f.write("$EndNodes\n$Elements\n%d\n" % len(tris))
        f.writelines("%d 2 2 1 1 %d %d %d\n" % (k + 1, t[0] + 1, t[1] + 1, t[2] + 1) for k, t in enumerate(tris))
        f.write("$EndElements\n")
PY
}

stat() { sed -n "s/^ *\"$1\": *\([^,]*\),*$/\1/p" "$2" | head -1; }

# run NAME ELE: tri2quad with time and peak memory.
run() {
  /usr/bin/time -f "%e %M" -o time.txt "$BIN/tri2quad" -q "$2" out.ele --stats s.json || true
  read -r wall kb < time.txt
  t=$(stat triangles s.json); q=$(stat quads s.json); s=$(stat steiner_points s.json)
  secs=$(stat seconds s.json); ok=$(stat within_bounds s.json); nc=$(stat non_convex s.json)
  mu=$(sed -n '/"median_mu"/s/.*: *\([0-9.]*\).*/\1/p' s.json | head -1)
  awk -v n="$1" -v t="$t" -v q="$q" -v s="$s" -v secs="$secs" -v wall="$wall" -v kb="$kb" -v ok="$ok" -v nc="$nc" -v mu="$mu" \
    'BEGIN { printf "  %-16s t=%9d  quads/t=%.3f  steiner/t=%.3f  run=%7.3f s  wall=%7.2f s  peak=%7.1f MB (%5.0f B/t)  median mu=%5.2f  non-convex=%s  bounds=%s\n",
             n, t, q / t, s / t, secs, wall, kb / 1024, kb * 1024 / t, mu, nc, ok }'
}

gmsh_row() {  # Blossom recombination of grid.msh
  command -v gmsh > /dev/null || { echo "  gmsh: not installed (apt-get install gmsh)"; return; }
  [ -s grid.msh ] || return
  cat > rec.geo <<'G'
Merge "grid.msh";
Mesh.RecombinationAlgorithm = 1;
Mesh.MshFileVersion = 2.2;
RecombineMesh;
Save "rec.msh";
G
  /usr/bin/time -f "%e %M" -o gtime.txt timeout 600 gmsh -v 0 rec.geo -0 > /dev/null 2>&1 || { echo "  gmsh: failed or over 600 s"; return; }
  read -r wall kb < gtime.txt
  python3 - "$wall" "$kb" <<'PY'
import math, sys
L = open("rec.msh").read().split("$Nodes")[1]
lines = L.split("\n")
n = int(lines[1]); P = {}
for l in lines[2:2 + n]:
    k, x, y, z = l.split(); P[int(k)] = (float(x), float(y))
E = open("rec.msh").read().split("$Elements")[1].split("\n")
ne = int(E[1]); quads = tris = 0; mus = []
def ang(a, b, c):
    ux, uy = b[0] - a[0], b[1] - a[1]; vx, vy = c[0] - a[0], c[1] - a[1]
    return math.degrees(math.atan2(abs(ux * vy - uy * vx), ux * vx + uy * vy))
def tmin(a, b, c): return min(ang(a, b, c), ang(b, c, a), ang(c, a, b))
for l in E[2:2 + ne]:
    f = l.split(); t = int(f[1]); nt = int(f[2]); v = [P[int(x)] for x in f[3 + nt:]]
    if t == 3:
        quads += 1; a, b, c, d = v
        mus.append(min(tmin(a, b, d), tmin(c, d, b), tmin(a, b, c), tmin(d, a, c)))
    elif t == 2: tris += 1
mus.sort()
print("  %-16s quads=%d triangles left=%d  wall=%.2f s  peak=%.1f MB  median mu=%.2f  mu<5: %d" %
      ("gmsh blossom", quads, tris, float(sys.argv[1]), int(sys.argv[2]) / 1024, mus[len(mus) // 2] if mus else 0,
       sum(1 for m in mus if m < 5)))
PY
}

echo "tri2quad on jittered grids (no constraints):"
sizes="71 224 708"
[ "${TRI2QUAD_BENCH_BIG:-0}" = 1 ] && sizes="$sizes 2237"
for n in $sizes; do
  grid "$n"
  run "grid 2x${n}^2" grid.ele
  if [ "$n" -le 224 ]; then gmsh_row; fi
done

if [ -x "$BIN/img2poly" ] && [ -x "$BIN/poly2tri" ]; then
  echo "tri2quad on a real constrained mesh (RatLungSlice1, img2poly + poly2tri):"
  "$BIN/img2poly" -q "$DATA/RatLungSlice1.mha" lung.poly --threshold 100
  "$BIN/poly2tri" -q lung.poly lung.1.ele
  run "lung" lung.1.ele
  "$BIN/poly2tri" -q lung.poly lung.2.ele --max-area 2
  run "lung max-area 2" lung.2.ele
fi
