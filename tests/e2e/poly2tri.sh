#!/usr/bin/env bash
# poly2tri end to end: Triangle's .poly conventions (comments, ids from 1,
# holes, regional attributes, markers), OFF polygons, angle and size bounds,
# outputs readable back (.ele/.node/.poly), and bad input (crossing segments,
# dangling id, truncated file) giving one line, exit 1 and no output.
set -euo pipefail
mkdir -p "$TMP"
cd "$TMP"
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

# A 10 x 10 square, ids from 1, a square hole (4..6)^2, a dividing segment at
# y = 2 with its own marker, two regions (below: 10, above: 20), comments.
cat > sq.poly <<'PEOF'
# vertices: id x y, one marker
10 2 0 1
1 0 0 5   # corner
2 10 0 5
3 10 10 5
4 0 10 5
5 4 4 0
6 6 4 0
7 6 6 0
8 4 6 0
9 0 2 0
10 10 2 0

11 1
1 1 2 1
2 2 10 1
3 10 3 1
4 3 4 1
5 4 9 1
6 9 1 1
7 5 6 2
8 6 7 2
9 7 8 2
10 8 5 2
11 9 10 3
# one hole
1
1 5 5
# two regions: x y attribute max-area
2
1 1 1 10 -1
2 1 9 20 -1
PEOF
expect 0 "$T" sq.poly sq.1.ele --stats s.json --svg sq.svg
[[ -s sq.1.ele && -s sq.1.node && -s sq.1.poly && -s sq.svg ]] || fail "outputs missing"
python3 check.py sq.1.ele sq.poly 20.7 > c.txt || { cat c.txt; fail "sq mesh"; }
python3 - <<'PYEOF' || fail "sq: area, hole, regions, markers, ids"
L = lambda f: [l for l in (x.split('#')[0].split() for x in open(f)) if l]
N, E, P = L("sq.1.node"), L("sq.1.ele"), L("sq.1.poly")
assert N[1][0] == '1' and E[1][0] == '1', "ids do not start at 1 like the input"
pts = {int(r[0]): (float(r[1]), float(r[2]), int(r[3])) for r in N[1:]}
area = 0
for r in E[1:]:
    a, b, c = (pts[int(t)] for t in r[1:4])
    A = ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) / 2
    area += A
    cx, cy = (a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3
    assert not (4 < cx < 6 and 4 < cy < 6), "a triangle in the hole"
    assert float(r[4]) == (10 if cy < 2 else 20), (cx, cy, r[4])
assert abs(area - 96) < 1e-9, area
# subsegments keep their markers; vertices on a segment carry its marker
ns = int(P[1][0])
for r in P[2:2 + ns]:
    a, b, m = pts[int(r[1])], pts[int(r[2])], int(r[3])
    if m == 2: assert max(abs((a[0] + b[0]) / 2 - 5), abs((a[1] + b[1]) / 2 - 5)) > 0.99
    if m == 3: assert a[1] == 2 and b[1] == 2
for x, y, m in pts.values():
    if (x, y) in [(0, 0), (10, 0), (10, 10), (0, 10)]: assert m == 5, (x, y, m)
    elif abs(max(abs(x - 5), abs(y - 5)) - 1) < 1e-12: assert m == 2, (x, y, m)
    elif y == 2 and 0 < x < 10: assert m == 3, (x, y, m)
PYEOF
grep -q '"triangles"' s.json || fail "stats"

# Angle and size bounds.
expect 0 "$T" sq.poly sq.2.ele --min-angle 30 --max-area 0.25
python3 check.py sq.2.ele sq.poly 30 > c.txt || { cat c.txt; fail "30 degrees"; }
python3 - <<'PYEOF' || fail "max area"
L = lambda f: [l for l in (x.split('#')[0].split() for x in open(f)) if l]
N, E = L("sq.2.node"), L("sq.2.ele")
pts = {int(r[0]): (float(r[1]), float(r[2])) for r in N[1:]}
for r in E[1:]:
    a, b, c = (pts[int(t)] for t in r[1:4])
    assert ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) / 2 <= 0.25 + 1e-12
PYEOF
expect 0 "$T" sq.poly sq.3.ele --max-edge 0.5 --min-angle 0
python3 - <<'PYEOF' || fail "max edge"
import math
L = lambda f: [l for l in (x.split('#')[0].split() for x in open(f)) if l]
N, E = L("sq.3.node"), L("sq.3.ele")
pts = {int(r[0]): (float(r[1]), float(r[2])) for r in N[1:]}
for r in E[1:]:
    p = [pts[int(t)] for t in r[1:4]]
    assert max(math.dist(p[k], p[(k + 1) % 3]) for k in range(3)) <= 0.5 + 1e-12
PYEOF
# A sharp input angle (about 6 degrees): the bound holds away from it.
printf '4 2 0 0\n0 0 0\n1 10 0\n2 10 1.1\n3 3 4\n4 0\n0 0 1\n1 1 2\n2 2 3\n3 3 0\n0\n' > sharp.poly
expect 0 "$T" sharp.poly sharp.1.ele --stats sh.json
python3 check.py sharp.1.ele sharp.poly 20.7 > c.txt || { cat c.txt; fail "sharp"; }
# The output .poly (vertices in the .node) is itself a valid input.
expect 0 "$T" sq.1.poly sq.4.ele
# OFF polygons: a square with a square inside it (two polygons).
printf 'OFF\n8 2 0\n0 0 0\n4 0 0\n4 4 0\n0 4 0\n1 1 0\n3 1 0\n3 3 0\n1 3 0\n4 0 1 2 3\n4 4 5 6 7\n' > sq.off
expect 0 "$T" sq.off off.1.ele
printf '0 2 0 0\n8 0\n0 0 1\n1 1 2\n2 2 3\n3 3 0\n4 4 5\n5 5 6\n6 6 7\n7 7 4\n' > off.poly
printf '8 2 0 0\n0 0 0\n1 4 0\n2 4 4\n3 0 4\n4 1 1\n5 3 1\n6 3 3\n7 1 3\n' > off.node
python3 check.py off.1.ele off.poly 20.7 > c.txt || { cat c.txt; fail "OFF input"; }
# Other output formats by extension.
for ext in off vtk msh svg; do expect 0 "$T" sq.poly "sq.$ext"; [[ -s "sq.$ext" ]] || fail "no .$ext"; done
grep -q '^\$MeshFormat' sq.msh || fail "msh header"

# Bad input: one line on stderr, exit 1, nothing written.
printf '4 2 0 0\n0 0 0\n1 2 2\n2 2 0\n3 0 2\n3 0\n0 0 1\n1 2 3\n2 0 2\n' > cross.poly
printf '3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n3 0\n0 0 1\n1 1 2\n2 2 7\n' > dangling.poly
head -c 60 sq.poly > trunc.poly
printf '3 2 0 0\n0 0 0\n1 nan 0\n2 0 1\n3 0\n0 0 1\n1 1 2\n2 2 0\n' > nan.poly
for bad in cross dangling trunc nan; do
  expect 1 "$T" $bad.poly $bad.1.ele
  [[ $(wc -l < err.txt) -eq 1 ]] || fail "$bad: error is not one line"
  grep -q "$bad.poly" err.txt || fail "$bad: the error does not name the file"
  [[ ! -e $bad.1.ele && ! -e $bad.1.node && ! -e $bad.1.poly ]] || fail "$bad: output written"
done
grep -q "line" err.txt || fail "no line number"
expect 1 "$T" missing.poly m.1.ele
expect 2 "$T" sq.poly x.1.ele --min-angle 40
expect 2 "$T" sq.poly x.1.ele --max-area 1 --max-edge 1
expect 2 "$T" sq.poly x.1.txt
[[ ! -e x.1.ele ]] || fail "output written on usage error"
echo "poly2tri e2e ok"
