#!/usr/bin/env bash
# img2poly end to end (then poly2tri on its output): a generated anisotropic
# binary image whose curve count is known, a three-label image, the sample
# RatLungSlice1.mha, stdout against the file output, and bad input. The
# Hausdorff distance to the pixel boundary is measured here, and meshes are
# checked by planar_check.py (CCW, conformity, angles, region attribute vs
# image).
source "$(dirname "$0")/lib.sh"
CHECK=$E2E/planar_check.py

# 80 x 60 binary image, spacing 0.5 x 0.8, origin (10, -5): a disc, a ring
# (two curves) and a blob touching the border; all well apart, so 4 curves.
# Also a three-label image, a 3D volume, a truncated file, huge sizes, a NaN.
images() {
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
}
input() { local d; d=$(dirname "$(shared shapes.nrrd images)"); for f in "$@"; do cp "$d/$f" .; done; }

# hausdorff POLY RAW W H OX OY SX SY THRESHOLD: the Hausdorff distance, in
# pixels, between the .poly's curves (the image rectangle aside) and the
# boundary between pixels above and below THRESHOLD (the image must be
# well-composed: no 2 x 2 block of diagonal pixels, so img2poly's repair
# leaves it as it is).
hausdorff() {
  python3 - "$@" <<'PY'
import math, sys
poly, raw, W, H = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
ox, oy, sx, sy, thr = (float(t) for t in sys.argv[5:10])
img = open(raw, 'rb').read()
fg = lambda x, y: img[x + W * y] >= thr
for y in range(H - 1):
    for x in range(W - 1):
        a, b, c, d = fg(x, y), fg(x + 1, y), fg(x, y + 1), fg(x + 1, y + 1)
        assert not (a == d and b == c and a != b), 'the test image is not well-composed at %d %d' % (x, y)
B = []  # pixel boundary edges, in pixel index coordinates
for y in range(H):
    for x in range(W):
        if x + 1 < W and fg(x, y) != fg(x + 1, y): B.append(((x + .5, y - .5), (x + .5, y + .5)))
        if y + 1 < H and fg(x, y) != fg(x, y + 1): B.append(((x - .5, y + .5), (x + .5, y + .5)))
L = [l.split('#')[0].split() for l in open(poly)]; L = [l for l in L if l]
n = int(L[0][0]); P = [((float(r[1]) - ox) / sx, (float(r[2]) - oy) / sy) for r in L[1:1 + n]]
ns = int(L[1 + n][0]); S = [(P[int(r[1]) - int(L[1][0])], P[int(r[2]) - int(L[1][0])]) for r in L[2 + n:2 + n + ns]]
side = lambda p: min(abs(p[0] + .5), abs(p[0] - W + .5), abs(p[1] + .5), abs(p[1] - H + .5)) < 1e-9
rect = lambda s: side(s[0]) and side(s[1]) and (abs(s[0][0] - s[1][0]) < 1e-9 or abs(s[0][1] - s[1][1]) < 1e-9)
C = [s for s in S if not rect(s)]
def dist(p, s):
    (ax, ay), (bx, by) = s
    ux, uy = bx - ax, by - ay; l2 = ux * ux + uy * uy
    t = max(0.0, min(1.0, ((p[0] - ax) * ux + (p[1] - ay) * uy) / l2)) if l2 else 0.0
    return math.hypot(p[0] - ax - t * ux, p[1] - ay - t * uy)
def samples(s, step=0.05):
    k = max(1, int(math.dist(*s) / step))
    return [(s[0][0] + (s[1][0] - s[0][0]) * i / k, s[0][1] + (s[1][1] - s[0][1]) * i / k) for i in range(k + 1)]
def bucket(segs):
    g = {}
    for s in segs:
        for p in samples(s, 0.5): g.setdefault((int(p[0] // 2), int(p[1] // 2)), set()).add(s)
    return g
def near(p, g, segs):
    best, r = math.inf, 1
    while True:
        cx, cy = int(p[0] // 2), int(p[1] // 2)
        found = [s for i in range(cx - r, cx + r + 1) for j in range(cy - r, cy + r + 1) for s in g.get((i, j), ())]
        if found: best = min(dist(p, s) for s in found)
        if best <= 2 * (r - 1) or r > 40: return min(best, min(dist(p, s) for s in segs)) if r > 40 else best
        r += 1
gB, gC = bucket(B), bucket(S)
h1 = max(near(p, gB, B) for s in C for p in samples(s))
h2 = max(near(p, gC, S) for s in B for p in samples(s, 0.25))
print('%.6f' % max(h1, h2))
PY
}

case_shapes_4_curves_within_tolerance_meshed() {
  input shapes.nrrd shapes.raw
  local E h
  for E in 0.5 1 2; do
    expect 0 img2poly shapes.nrrd shapes.poly --threshold 100 --tolerance $E --stats s.json --svg shapes.svg || continue
    [[ $(json s.json curves) -eq 4 ]] || fail "E=$E: $(json s.json curves) curves, want 4"
    h=$(hausdorff shapes.poly shapes.raw 80 60 10 -5 0.5 0.8 100) || { fail "E=$E: Hausdorff not measured"; continue; }
    python3 -c "import sys; sys.exit(not float(sys.argv[1]) <= float(sys.argv[2]) + 1e-9)" "$h" $E ||
      fail "E=$E: Hausdorff distance $h pixels to the pixel boundary"
    local segs; segs=$(grep -v '^ *#' shapes.poly | sed -n "$(( $(count shapes.poly) + 2 ))p" | cut -d' ' -f1)
    [[ $(grep -c '<line' shapes.svg) == "$segs" ]] || fail "E=$E: the SVG does not draw the $segs segments"
    expect 0 poly2tri shapes.poly shapes.1.ele || continue
    # Image index of a world point: (x - 10) / 0.5, (y + 5) / 0.8.
    python3 "$CHECK" shapes.1.ele shapes.poly 20.7 shapes.raw 80 60 10 -5 0.5 0.8 100 $E > c.txt ||
      fail "mesh check, E=$E: $(cat c.txt)"
  done
}

case_rectangle_in_world_coordinates() {
  input shapes.nrrd
  expect 0 img2poly shapes.nrrd shapes.poly --threshold 100
  python3 - <<'PYEOF' || fail "rectangle not in world coordinates"
L = [l.split('#')[0].split() for l in open("shapes.poly")]
L = [l for l in L if l]
n = int(L[0][0])
xs = [float(r[1]) for r in L[1:1 + n]]; ys = [float(r[2]) for r in L[1:1 + n]]
# pixels 0..79 at x = 10 + 0.5 i, half a pixel beyond; y = -5 + 0.8 j, j = 0..59
assert abs(min(xs) - (10 - 0.25)) < 1e-9 and abs(max(xs) - (10 + 0.5 * 79 + 0.25)) < 1e-9, (min(xs), max(xs))
assert abs(min(ys) - (-5 - 0.4)) < 1e-9 and abs(max(ys) - (-5 + 0.8 * 59 + 0.4)) < 1e-9, (min(ys), max(ys))
PYEOF
}

case_three_labels_junctions_interfaces_attributes() {
  input labels.nrrd
  expect 0 img2poly labels.nrrd labels.poly --stats l.json
  [[ $(json l.json junctions) -gt 0 ]] || fail "no junctions"
  python3 -c "import json; f = json.load(open('l.json'))['interfaces']; assert sorted(tuple(i['labels']) for i in f) == [(1, 2), (1, 3), (2, 3)], f" ||
    fail "interfaces"
  expect 0 poly2tri labels.poly labels.1.ele
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
  expect 0 img2poly labels.nrrd l3.poly --label 3 --stats l3.json
  [[ $(json l3.json curves) -eq 1 ]] || fail "--label 3: want 1 curve"
}

case_lung_slice_meshed() {
  expect 0 img2poly "$DATA/RatLungSlice1.mha" lung.poly --threshold 60 --svg lung.svg
  expect 0 poly2tri lung.poly lung.1.ele
  python3 "$CHECK" lung.1.ele lung.poly 20.7 "$DATA/RatLungSlice1.raw" 128 128 0 0 1 1 60 1 > c.txt || fail "lung mesh: $(cat c.txt)"
}

# The simplification's queue breaks cost ties by the order it was filled
# in, which CGAL takes from constraint addresses: the output must not change
# with the heap layout (glibc's tunables move the allocations; before the
# tie-break each of these gave another lung .poly).
case_output_does_not_depend_on_heap_layout() {
  expect 0 img2poly "$DATA/RatLungSlice1.mha" base.poly --threshold 60
  local t
  for t in glibc.malloc.mmap_threshold=4096 glibc.malloc.tcache_count=0; do
    GLIBC_TUNABLES=$t expect 0 img2poly "$DATA/RatLungSlice1.mha" t.poly --threshold 60
    cmp -s t.poly base.poly || fail "GLIBC_TUNABLES=$t: another .poly"
  done
}

case_stdin_stdout_are_the_files() {
  input shapes.nrrd
  expect 0 img2poly shapes.nrrd file.poly --threshold 100
  OUT=stdout.poly expect 0 img2poly shapes.nrrd - --threshold 100
  cmp -s stdout.poly file.poly || fail "OUT - differs from OUT file.poly"
  IN=shapes.nrrd OUT=stdin.poly expect 0 img2poly - - --threshold 100
  cmp -s stdin.poly file.poly || fail "IN - differs from IN shapes.nrrd"
}

case_bad_input_one_line_exit_1_2_without_output() {
  input vol.nrrd trunc.nrrd huge.nrrd nan.nrrd shapes.nrrd labels.nrrd
  expect 1 img2poly vol.nrrd bad.poly
  expect 1 img2poly trunc.nrrd bad.poly
  expect 1 img2poly huge.nrrd bad.poly
  expect 1 img2poly nan.nrrd bad.poly --threshold 0.5
  expect 1 img2poly missing.nrrd bad.poly
  expect 1 img2poly shapes.nrrd bad.poly --threshold 250
  expect 1 img2poly labels.nrrd bad.poly --label 9
  [[ $(wc -l < err.txt) -eq 1 ]] || fail "error is not one line"
  expect 2 img2poly shapes.nrrd bad.poly --tolerance -1
  expect 2 img2poly shapes.nrrd bad.txt
  [[ ! -e bad.poly && ! -e bad.txt ]] || fail "output written on error"
}

# Exit 3: simplified without the tolerance stop (the hidden test-only
# --skip-tolerance-stop), the final Hausdorff measure must find E broken:
# exit 3, the .poly written (file and stdout alike), fewer vertices than
# within E, and still a PSLG poly2tri meshes.
case_exit_3_when_the_tolerance_stop_is_skipped() {
  input shapes.nrrd
  expect 0 img2poly shapes.nrrd within.poly --threshold 100
  expect 3 img2poly shapes.nrrd skip.poly --threshold 100 --skip-tolerance-stop --stats s.json
  grep -q "^img2poly: guarantee not met: the Hausdorff bound" err.txt || fail "no guarantee message: $(cat err.txt)"
  python3 -c 'import json, sys; d = json.load(open("s.json")); sys.exit(not d["hausdorff"] > d["tolerance"])' ||
    fail "stats: Hausdorff within the bound: $(cat s.json)"
  (($(count skip.poly) < $(count within.poly))) || fail "skip.poly has $(count skip.poly) vertices, within.poly $(count within.poly)"
  OUT=skip-stdout.poly expect 3 img2poly shapes.nrrd - --threshold 100 --skip-tolerance-stop
  cmp -s skip-stdout.poly skip.poly || fail "OUT - differs from OUT skip.poly on exit 3"
  expect 0 poly2tri skip.poly skip.1.ele
}

run_cases "$@"
