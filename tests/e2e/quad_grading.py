#!/usr/bin/env python3
"""quad_grading.py MESH.ele [MAX_RATIO [MAX_SHARE [MAX_TOP]]] (python3 stdlib only)

The size grading of a planar quad mesh (Triangle .ele + .node): for every
edge two quads share, the ratio of their sizes (the square roots of their
areas, larger over smaller). Prints "max R p99 R largest S" (S: the largest
quad's size over the shorter side of the mesh's bounding box). Exit 1 when
the 99th percentile of the ratios is over MAX_RATIO, the largest quad over
MAX_SHARE of the shorter side, or the largest ratio over MAX_TOP.
"""
import math, sys


def rows(path):
    return [l.split('#', 1)[0].split() for l in open(path) if l.split('#', 1)[0].split()]


def main():
    ele = sys.argv[1]
    N, E = rows(ele[:-4] + '.node'), rows(ele)
    first = int(N[1][0])
    P = [(float(r[1]), float(r[2])) for r in N[1:1 + int(N[0][0])]]
    k = int(E[0][1])
    Q = [[int(t) - first for t in r[1:1 + k]] for r in E[1:1 + int(E[0][0])]]
    size = [math.sqrt(abs(sum(P[q[i]][0] * P[q[i - 3]][1] - P[q[i - 3]][0] * P[q[i]][1] for i in range(4))) / 2)
            for q in Q]
    owner = {}
    ratios = []
    for f, q in enumerate(Q):
        for i in range(4):
            e = (min(q[i], q[i - 3]), max(q[i], q[i - 3]))
            if e in owner:
                a, b = size[owner[e]], size[f]
                ratios.append(max(a, b) / min(a, b))
            else:
                owner[e] = f
    ratios.sort()
    xs, ys = [p[0] for p in P], [p[1] for p in P]
    side = min(max(xs) - min(xs), max(ys) - min(ys))
    top, p99, largest = ratios[-1], ratios[int(0.99 * (len(ratios) - 1))], max(size) / side
    print("max %.3f p99 %.3f largest %.4f" % (top, p99, largest))
    ok = len(sys.argv) < 3 or p99 <= float(sys.argv[2])
    ok = ok and (len(sys.argv) < 4 or largest <= float(sys.argv[3]))
    ok = ok and (len(sys.argv) < 5 or top <= float(sys.argv[4]))
    return 0 if ok else 1


sys.exit(main())
