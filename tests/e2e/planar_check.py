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
