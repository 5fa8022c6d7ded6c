#!/usr/bin/env python3
"""gmsh_triangles.py IN.msh OUT (python3 stdlib only): the triangles of a Gmsh 2.2 mesh as
Triangle's OUT.node, OUT.ele (the physical surface as the region attribute) and OUT.poly (segments:
the boundary edges, marker 1, and the edges between regions, marker 2; their vertices carry the
marker too): a triangulation made by someone else, for tri2quad."""
import sys
text = open(sys.argv[1]).read()
L = text.split("$Nodes")[1].split("\n")
n = int(L[1]); ids = {}; P = []
for l in L[2:2 + n]:
    k, x, y, _ = l.split(); ids[int(k)] = len(P); P.append((float(x), float(y)))
E = text.split("$Elements")[1].split("\n")
T, R = [], []
for l in E[2:2 + int(E[1])]:
    f = l.split()
    if f[1] != "2": continue
    nt = int(f[2]); a, b, c = (ids[int(x)] for x in f[3 + nt:6 + nt])
    # counter-clockwise
    if (P[b][0] - P[a][0]) * (P[c][1] - P[a][1]) - (P[b][1] - P[a][1]) * (P[c][0] - P[a][0]) < 0: b, c = c, b
    T.append((a, b, c)); R.append(int(f[3]) if nt else 0)
edges = {}
for i, t in enumerate(T):
    for j in range(3):
        edges.setdefault(tuple(sorted((t[j], t[(j + 1) % 3]))), []).append(i)
S = sorted((e, 1 if len(ts) == 1 else 2) for e, ts in edges.items() if len(ts) == 1 or R[ts[0]] != R[ts[1]])
mark = {}
for (a, b), m in S: mark[a] = mark[b] = max(mark.get(a, 0), m)
out = sys.argv[2]
used = sorted(set(v for t in T for v in t)); new = {v: k for k, v in enumerate(used)}
with open(out + ".node", "w") as f:
    f.write("%d 2 0 1\n" % len(used))
    f.writelines("%d %.17g %.17g %d\n" % (new[v], P[v][0], P[v][1], mark.get(v, 0)) for v in used)
with open(out + ".ele", "w") as f:
    f.write("%d 3 1\n" % len(T))
    f.writelines("%d %d %d %d %d\n" % (k, new[t[0]], new[t[1]], new[t[2]], R[k]) for k, t in enumerate(T))
with open(out + ".poly", "w") as f:
    f.write("0 2 0 1\n%d 1\n" % len(S))
    f.writelines("%d %d %d %d\n" % (k, new[a], new[b], m) for k, ((a, b), m) in enumerate(S))
    f.write("0\n")
