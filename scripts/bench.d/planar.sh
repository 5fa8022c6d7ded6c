#!/usr/bin/env bash
# img2poly + poly2tri on 512x512 and 2048x2048 slices: RatLungSlice1 (128^2)
# upscaled bilinearly (so boundaries are smooth at the new resolution), then
# thresholded by img2poly. Prints time and sizes of both stages.
set -euo pipefail
BIN=${1:?usage: planar.sh TOOL_FOLDER}
DATA=$(cd "$(dirname "$0")/../../share/data" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
for n in 512 2048; do
  python3 - "$DATA/RatLungSlice1.raw" $n <<'PYEOF'
import sys
src = open(sys.argv[1], 'rb').read(); N = int(sys.argv[2]); S = 128
out = bytearray(N * N)
for y in range(N):
    fy = min(max((y + 0.5) * S / N - 0.5, 0), S - 1); y0 = min(int(fy), S - 2); ty = fy - y0
    r0, r1 = y0 * S, (y0 + 1) * S
    for x in range(N):
        fx = min(max((x + 0.5) * S / N - 0.5, 0), S - 1); x0 = min(int(fx), S - 2); tx = fx - x0
        a = src[r0 + x0] * (1 - tx) + src[r0 + x0 + 1] * tx
        b = src[r1 + x0] * (1 - tx) + src[r1 + x0 + 1] * tx
        out[x + N * y] = int(a * (1 - ty) + b * ty + 0.5)
sp = S / N
hdr = ("NRRD0004\ntype: uint8\ndimension: 2\nsizes: %d %d\nspace dimension: 2\n"
       "space directions: (%g,0) (0,%g)\nspace origin: (0,0)\nencoding: raw\n\n") % (N, N, sp, sp)
open("slice%d.nrrd" % N, "wb").write(hdr.encode() + out)
PYEOF
  for E in 1 2; do
    t0=$(date +%s.%N)
    "$BIN/img2poly" slice$n.nrrd s$n.poly --threshold 60 --tolerance $E --stats p.json -q
    t1=$(date +%s.%N)
    "$BIN/poly2tri" s$n.poly s$n.1.ele --stats t.json -q
    t2=$(date +%s.%N)
    python3 - "$n" "$E" "$t0" "$t1" "$t2" <<'PYEOF'
import json, sys
n, E, t0, t1, t2 = sys.argv[1], sys.argv[2], *map(float, sys.argv[3:])
p, t = json.load(open("p.json")), json.load(open("t.json"))
print("%sx%s E=%s  img2poly %.2fs: %d curves, %d -> %d vertices, %d regions, Hausdorff %.3f px" %
      (n, n, E, t1 - t0, p["curves"], p["boundary_vertices"], p["vertices"], p["regions"], p["hausdorff"]))
print("%sx%s E=%s  poly2tri %.2fs: %d triangles, %d vertices (%d Steiner), min angle %.1f (%.1f away from small input angles)" %
      (n, n, E, t2 - t1, t["triangles"], t["vertices"], t["steiner_points"], t["min_angle"],
       t["min_angle_away_from_small_input_angles"]))
PYEOF
  done
done
