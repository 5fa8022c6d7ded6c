#!/usr/bin/env python3
"""Independent checks of a planar quad mesh (python3 stdlib only).

  quad_check.py OUT.ele [IN.ele] [--fixed] [--on-sides N]

OUT.ele with its .node (Triangle's formats, ids from 0 or 1): every element
has 4 nodes, strictly convex and counterclockwise (in floating point, and
exactly, in fractions of the file's decimals, where that is too close to
call); edge to edge (each edge in one or two
quads, once each way); prints quads, area, min and mean Joe's-mu-free
quality (smallest and mean of the quads' smallest angles, degrees). With
IN.ele (triangles or quads): the same area, and the same area per region
attribute; --fixed: every input node with a nonzero boundary marker is an
output node at the same place; --on-sides N: the input is the square
[0, N]^2 and every output node on its sides in the input lies on its sides,
its corners kept. Exit 1 naming the failures.
"""
import math, sys
from fractions import Fraction


def rows(path):
    return [l.split('#', 1)[0].split() for l in open(path) if l.split('#', 1)[0].split()]


def read(ele):
    N, E = rows(ele[:-4] + '.node'), rows(ele)
    nn, _, na, nm = (int(t) for t in N[0][:4])
    first = int(N[1][0])
    pts = [(float(r[1]), float(r[2])) for r in N[1:1 + nn]]
    exact = [(r[1], r[2]) for r in N[1:1 + nn]]
    marks = [int(r[3 + na]) if nm else 0 for r in N[1:1 + nn]]
    ne, k, ea = int(E[0][0]), int(E[0][1]), int(E[0][2]) if len(E[0]) > 2 else 0
    els = [([int(t) - first for t in r[1:1 + k]], r[1 + k] if ea else '0') for r in E[1:1 + ne]]
    return pts, marks, els, exact


def area(p, el):
    return sum(p[el[i]][0] * p[el[(i + 1) % len(el)]][1] - p[el[(i + 1) % len(el)]][0] * p[el[i]][1]
               for i in range(len(el))) / 2


def main(argv):
    bad = []
    out = [a for a in argv if a.endswith('.ele')]
    P, M, E, X = read(out[0])
    edges = {}
    worst, smallest = [], []
    for q, (el, _) in enumerate(E):
        if len(el) != 4: bad.append('element %d has %d nodes' % (q, len(el))); continue
        for i in range(4):
            a, b, c = P[el[i]], P[el[(i + 1) % 4]], P[el[(i + 2) % 4]]
            turn = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])
            scale = max(abs(b[0] - a[0]) + abs(b[1] - a[1]), abs(c[0] - b[0]) + abs(c[1] - b[1])) ** 2
            if abs(turn) <= 1e-12 * scale:  # too close to call in floating point
                a, b, c = ((Fraction(X[v][0]), Fraction(X[v][1])) for v in (el[i], el[(i + 1) % 4], el[(i + 2) % 4]))
                turn = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])
            if turn <= 0:
                bad.append('quad %d not strictly convex counterclockwise' % q); break
            e = (el[i], el[(i + 1) % 4])
            if e in edges: bad.append('edge %s twice the same way' % (e,))
            edges[e] = q
        ang = []
        for i in range(4):
            a, b, c = (P[el[(i + j) % 4]] for j in (3, 0, 1))
            u, v = (a[0] - b[0], a[1] - b[1]), (c[0] - b[0], c[1] - b[1])
            ang.append(math.degrees(math.atan2(abs(u[0] * v[1] - u[1] * v[0]), u[0] * v[0] + u[1] * v[1])))
        smallest.append(min(ang))
    used = {v for el, _ in E for v in el}
    if len(used) != len(P): bad.append('%d nodes in no quad' % (len(P) - len(used)))
    A = sum(area(P, el) for el, _ in E)
    if E: print('quads %d area %.9g min_angle %.4f mean_min_angle %.4f' % (len(E), A, min(smallest),
                                                                          sum(smallest) / len(smallest)))
    if len(out) > 1:
        p, m, e, _ = read(out[1])
        regions = lambda pts, els: {r: sum(area(pts, el) for el, a in els if a == r) for r in {a for _, a in els}}
        ri, ro = regions(p, e), regions(P, E)
        if {float(k) for k in ri} != {float(k) for k in ro}: bad.append('regions %s became %s' % (sorted(ri), sorted(ro)))
        else:
            for k in ri:
                ko = next(x for x in ro if float(x) == float(k))
                if abs(ri[k] - ro[ko]) > 1e-9 * abs(ri[k]): bad.append('region %s area changed' % k)
        place = set(P)
        if '--fixed' in argv:
            moved = sum(1 for x, mk in zip(p, m) if mk and x not in place)
            if moved: bad.append('%d boundary nodes moved' % moved)
        if '--on-sides' in argv:
            n = float(argv[argv.index('--on-sides') + 1])
            side = lambda x: x[0] in (0, n) or x[1] in (0, n)
            if sum(map(side, p)) != sum(map(side, P)): bad.append('a node left (or joined) the square\'s sides')
            for c in ((0, 0), (0, n), (n, 0), (n, n)):
                if c not in place: bad.append('corner %s moved' % (c,))
            if any(not (0 <= x[0] <= n and 0 <= x[1] <= n) for x in P): bad.append('a node outside the square')
    if bad:
        print('quad_check.py: ' + '; '.join(bad[:5]), file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
