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

cat > check.py <<'PYEOF'
# Independent checks of a poly2tri mesh (stdlib only): CCW non-degenerate
# triangles, every PSLG segment a chain of mesh edges, smallest angle >= A
# except near small input angles (a vertex within the disc around an apex
# where two segments meet below 60 degrees, radius the shorter of the two),
# and optionally the region attribute against the image under each centroid.
import math, sys

def lines(path):
    out = []
    for l in open(path):
        l = l.split('#', 1)[0].split()
        if l: out.append(l)
    return out

def read_node(path):
    L = lines(path); n, _, na, nm = (int(t) for t in L[0][:4])
    first = int(L[1][0]) if n else 0
    return first, [(float(r[1]), float(r[2])) for r in L[1:1 + n]], [int(r[3 + na]) if nm else 0 for r in L[1:1 + n]]

def read_poly(path):
    L = lines(path); n = int(L[0][0]); pos = 1
    if n:
        first = int(L[1][0]); pts = [(float(r[1]), float(r[2])) for r in L[1:1 + n]]
    else:
        first, pts, _ = read_node(path[:-5] + '.node')
    pos += n
    ns, sm = int(L[pos][0]), int(L[pos][1]); pos += 1
    segs = [(int(r[1]) - first, int(r[2]) - first, int(r[3]) if sm else 0) for r in L[pos:pos + ns]]
    return pts, segs

def read_ele(path):
    first, pts, marks = read_node(path[:-4] + '.node')
    L = lines(path); n, per, na = (int(t) for t in L[0][:3])
    els = [[int(t) - first for t in r[1:1 + per]] for r in L[1:1 + n]]
    attr = [float(r[1 + per]) if na else 0.0 for r in L[1:1 + n]]
    return pts, els, attr, marks

def seg_dist(p, a, b):
    dx, dy = b[0] - a[0], b[1] - a[1]; l2 = dx * dx + dy * dy
    t = max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2)) if l2 else 0.0
    return math.hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy)

def angle(p, q, r):
    ux, uy, vx, vy = q[0] - p[0], q[1] - p[1], r[0] - p[0], r[1] - p[1]
    return math.degrees(math.atan2(abs(ux * vy - uy * vx), ux * vx + uy * vy))

def main(a):
    ele, poly, amin = a[0], a[1], float(a[2])
    pts, els, attr, marks = read_ele(ele)
    ppts, segs = read_poly(poly)
    fail = []
    edges = set(); area = 0.0
    for e in els:
        A, B, C = (pts[i] for i in e)
        cr = (B[0] - A[0]) * (C[1] - A[1]) - (C[0] - A[0]) * (B[1] - A[1])
        if cr <= 0: fail.append('not ccw'); break
        area += cr / 2
        for k in range(3): edges.add(frozenset((e[k], e[(k + 1) % 3])))
    # conformity, with a grid of buckets to find the vertices on each segment
    xs = [p[0] for p in pts]; ys = [p[1] for p in pts]
    x0, y0 = min(xs), min(ys); h = max(max(xs) - x0, max(ys) - y0) / 200 or 1
    grid = {}
    for i, p in enumerate(pts): grid.setdefault((int((p[0] - x0) / h), int((p[1] - y0) / h)), []).append(i)
    apex = []  # (point, radius): small input angles and their discs
    at = {}
    for s, (u, v, m) in enumerate(segs): at.setdefault(u, []).append(s); at.setdefault(v, []).append(s)
    seglen = lambda s: math.dist(ppts[segs[s][0]], ppts[segs[s][1]])
    for v, ss in at.items():
        for i in range(len(ss)):
            for j in range(i + 1, len(ss)):
                w1 = segs[ss[i]][0] if segs[ss[i]][1] == v else segs[ss[i]][1]
                w2 = segs[ss[j]][0] if segs[ss[j]][1] == v else segs[ss[j]][1]
                if angle(ppts[v], ppts[w1], ppts[w2]) < 60: apex.append((ppts[v], min(seglen(ss[i]), seglen(ss[j]))))
    for s, (u, v, m) in enumerate(segs):
        a_, b_ = ppts[u], ppts[v]; L = math.hypot(b_[0] - a_[0], b_[1] - a_[1])
        on = []
        for gx in range(int((min(a_[0], b_[0]) - x0) / h) - 1, int((max(a_[0], b_[0]) - x0) / h) + 2):
            for gy in range(int((min(a_[1], b_[1]) - y0) / h) - 1, int((max(a_[1], b_[1]) - y0) / h) + 2):
                for i in grid.get((gx, gy), []):
                    if seg_dist(pts[i], a_, b_) < 1e-9 * L:
                        on.append(((pts[i][0] - a_[0]) * (b_[0] - a_[0]) + (pts[i][1] - a_[1]) * (b_[1] - a_[1]), i))
        on.sort()
        if len(on) < 2: fail.append('segment %d has no mesh vertices' % s); continue
        for k in range(len(on) - 1):
            if frozenset((on[k][1], on[k + 1][1])) not in edges: fail.append('segment %d not covered' % s); break
    worst = 180.0; below = 0
    for e in els:
        m = min(angle(pts[e[0]], pts[e[1]], pts[e[2]]), angle(pts[e[1]], pts[e[2]], pts[e[0]]), angle(pts[e[2]], pts[e[0]], pts[e[1]]))
        if m < amin - 1e-6:
            below += 1
            if not any(math.dist(pts[i], c) <= r * (1 + 1e-9) for i in e for c, r in apex): worst = min(worst, m)
    if worst < amin - 1e-6: fail.append('angle %.3f below %.3f away from small input angles' % (worst, amin))
    res = {'triangles': len(els), 'area': area, 'below_bound_near_small_angles': below}
    if len(a) > 3:  # RAW W H OX OY SX SY THRESHOLD TOL: attributes against the image
        raw, W, H = a[3], int(a[4]), int(a[5]); ox, oy, sx, sy, thr, tol = (float(t) for t in a[6:12])
        img = open(raw, 'rb').read()
        def lab(x, y):
            return 1 if 0 <= x < W and 0 <= y < H and img[x + W * y] >= thr else 0
        r = int(math.ceil(tol)) + 1; bad = 0; mism = 0
        for e, at_ in zip(els, attr):
            cx = sum(pts[i][0] for i in e) / 3; cy = sum(pts[i][1] for i in e) / 3
            x, y = int(round((cx - ox) / sx)), int(round((cy - oy) / sy))
            if lab(x, y) != at_:
                mism += 1
                if not any(lab(x + i, y + j) == at_ for i in range(-r, r + 1) for j in range(-r, r + 1)): bad += 1
        res['attribute_mismatch_near_boundary'] = mism
        if bad: fail.append('%d triangles with a wrong region attribute' % bad)
    print(res, fail)
    return 1 if fail else 0

sys.exit(main(sys.argv[1:]))
PYEOF

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
