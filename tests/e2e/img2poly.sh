#!/usr/bin/env bash
# img2poly end to end (then poly2tri on its output): a generated anisotropic
# binary image whose curve count is known, a three-label image, the sample
# RatLungSlice1.mha, and bad input. Meshes are checked by an independent
# stdlib-only checker (CCW, conformity, angles, region attribute vs image).
set -euo pipefail
mkdir -p "$TMP"
cd "$TMP"
P="$BIN/img2poly"
T="$BIN/poly2tri"
fail() { echo "FAIL: $*" >&2; exit 1; }
expect() {
  local want=$1; shift
  set +e; "$@" > out.txt 2> err.txt; local got=$?; set -e
  [[ $got -eq $want ]] || { cat err.txt >&2; fail "exit $got (want $want): $*"; }
}
json() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1" "$2"; }

cp "$SRC/tests/e2e/planar_check.py" check.py  # independent mesh checker, shared with the other planar e2e test

# 80 x 60 binary image, spacing 0.5 x 0.8, origin (10, -5): a disc, a ring
# (two curves) and a blob touching the border; all well apart, so 4 curves.
python3 - <<'PYEOF'
import math
W, H = 80, 60
img = bytearray(W * H)
for y in range(H):
    for x in range(W):
        r1, r2 = math.hypot(x - 20.3, y - 30.2), math.hypot(x - 55.4, y - 25.7)
        on = r1 < 6.5 or 10 < r2 < 16 or (x > 70 and y > 48)
        img[x + W * y] = 200 if on else 10
hdr = ("NRRD0004\ntype: uint8\ndimension: 2\nsizes: %d %d\nspace dimension: 2\n"
       "space directions: (0.5,0) (0,0.8)\nspace origin: (10,-5)\nencoding: raw\n\n") % (W, H)
open("shapes.nrrd", "wb").write(hdr.encode() + img)
open("shapes.raw", "wb").write(img)
# Three labels meeting at junctions.
L = bytearray(W * H)
for y in range(H):
    for x in range(W):
        L[x + W * y] = 3 if math.hypot(x - 40, y - 30) < 12 else (1 if x < 40 else 2)
hdr = "NRRD0004\ntype: uint8\ndimension: 2\nsizes: %d %d\nencoding: raw\n\n" % (W, H)
open("labels.nrrd", "wb").write(hdr.encode() + L)
# A 3D volume and a truncated file.
open("vol.nrrd", "wb").write(b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n\n" + bytes(64))
open("trunc.nrrd", "wb").write(hdr.encode() + L[:100])
# Huge sizes announced in a tiny file; a NaN in a float image.
open("huge.nrrd", "wb").write(b"NRRD0004\ntype: uint8\ndimension: 2\nsizes: 100000 100000\nencoding: raw\n\n" + bytes(100))
import struct
open("nan.nrrd", "wb").write(b"NRRD0004\ntype: float\ndimension: 2\nsizes: 4 3\nendian: little\nencoding: raw\n\n"
                             + struct.pack("<12f", *([1.0] * 5 + [float("nan")] + [0.0] * 6)))
PYEOF

for E in 0.5 1 2; do
  expect 0 "$P" shapes.nrrd shapes.poly --threshold 100 --tolerance $E --stats s.json --svg shapes.svg
  [[ $(json s.json curves) -eq 4 ]] || fail "E=$E: $(json s.json curves) curves, want 4"
  python3 -c "import json; h = json.load(open('s.json'))['hausdorff']; assert h <= $E + 1e-9, h" || fail "Hausdorff above $E"
  grep -q "<svg" shapes.svg || fail "no SVG"
  expect 0 "$T" shapes.poly shapes.1.ele
  # Image index of a world point: (x - 10) / 0.5, (y + 5) / 0.8.
  python3 check.py shapes.1.ele shapes.poly 20.7 shapes.raw 80 60 10 -5 0.5 0.8 100 $E > c.txt || { cat c.txt; fail "mesh check, E=$E"; }
done
# World coordinates: the rectangle spans the image in physical units.
python3 - <<'PYEOF' || fail "rectangle not in world coordinates"
L = [l.split('#')[0].split() for l in open("shapes.poly")]
L = [l for l in L if l]
n = int(L[0][0])
xs = [float(r[1]) for r in L[1:1 + n]]; ys = [float(r[2]) for r in L[1:1 + n]]
# pixels 0..79 at x = 10 + 0.5 i, half a pixel beyond; y = -5 + 0.8 j, j = 0..59
assert abs(min(xs) - (10 - 0.25)) < 1e-9 and abs(max(xs) - (10 + 0.5 * 79 + 0.25)) < 1e-9, (min(xs), max(xs))
assert abs(min(ys) - (-5 - 0.4)) < 1e-9 and abs(max(ys) - (-5 + 0.8 * 59 + 0.4)) < 1e-9, (min(ys), max(ys))
PYEOF

# Three labels: junctions, one marker per touching pair, attributes = labels.
expect 0 "$P" labels.nrrd labels.poly --stats l.json
[[ $(json l.json junctions) -gt 0 ]] || fail "no junctions"
python3 -c "import json; f = json.load(open('l.json'))['interfaces']; assert sorted(tuple(i['labels']) for i in f) == [(1, 2), (1, 3), (2, 3)], f" || fail "interfaces"
expect 0 "$T" labels.poly labels.1.ele
python3 - <<'PYEOF' || fail "label attributes"
import math
L = [l.split('#')[0].split() for l in open("labels.1.ele")]; L = [l for l in L if l]
N = [l.split('#')[0].split() for l in open("labels.1.node")]; N = [l for l in N if l]
pts = {int(r[0]): (float(r[1]), float(r[2])) for r in N[1:]}
bad = 0
for r in L[1:]:
    c = [pts[int(t)] for t in r[1:4]]
    x = sum(p[0] for p in c) / 3; y = sum(p[1] for p in c) / 3
    d = math.hypot(x - 40, y - 30)
    want = 3 if d < 12 else (1 if x < 40 else 2)
    # far from the curves (circle r 12, line x = 39.5) the label must match
    if abs(d - 12) > 2 and abs(x - 39.5) > 2 and float(r[4]) != want: bad += 1
assert bad == 0, bad
PYEOF
# --label keeps some labels, the others become 0.
expect 0 "$P" labels.nrrd l3.poly --label 3 --stats l3.json
[[ $(json l3.json curves) -eq 1 ]] || fail "--label 3: want 1 curve"

# The sample slice.
expect 0 "$P" "$DATA/RatLungSlice1.mha" lung.poly --threshold 60 --svg lung.svg --stats lung.json
expect 0 "$T" lung.poly lung.1.ele
python3 check.py lung.1.ele lung.poly 20.7 "$DATA/RatLungSlice1.raw" 128 128 0 0 1 1 60 1 > c.txt || { cat c.txt; fail "lung mesh"; }

# Bad input: one line, exit 1 (2 for usage), no output.
rm -f bad.poly
expect 1 "$P" vol.nrrd bad.poly
expect 1 "$P" trunc.nrrd bad.poly
expect 1 "$P" huge.nrrd bad.poly
expect 1 "$P" nan.nrrd bad.poly --threshold 0.5
expect 1 "$P" missing.nrrd bad.poly
expect 1 "$P" shapes.nrrd bad.poly --threshold 250
expect 1 "$P" labels.nrrd bad.poly --label 9
[[ $(wc -l < err.txt) -eq 1 ]] || fail "error is not one line"
expect 2 "$P" shapes.nrrd bad.poly --tolerance -1
expect 2 "$P" shapes.nrrd bad.txt
[[ ! -e bad.poly && ! -e bad.txt ]] || fail "output written on error"
echo "img2poly e2e ok"
