#!/usr/bin/env python3
"""Benchmark helper (not a test): the figures scripts/bench.d/implicit2mesh.sh
prints for any mesher's triangle OFF file, measured the same way for all.
  mesh_metrics.py MESH.off IMPLICIT.nrrd IMPLICIT_EVAL
Prints "triangles min_angle_deg max_normal_jump_deg max_abs_f_vx":
the smallest triangle angle; the largest angle between the normals of two
triangles sharing an edge (edges in exactly two triangles); max |f| at the
triangles' centroids in voxels of the smallest spacing (f from the implicit
function file, evaluated by implicit-eval).
  mesh_metrics.py MESH.off IMPLICIT.nrrd IMPLICIT_EVAL --sampled
prints instead "triangles max p99 mean" of each triangle's largest |f| (in
voxels) over 15 points (barycentric coordinates in quarters): the error
inside the triangles, which centroids alone miss."""
import re
import subprocess
import sys

import numpy as np


def read_off(path):
    text = open(path).read()
    text = re.sub(r'#[^\n]*', ' ', text)
    tok = text.split()
    if not tok or not tok[0].endswith('OFF'):
        sys.exit('mesh_metrics: %s: not OFF' % path)
    nv, nf = int(tok[1]), int(tok[2])
    v = np.array(tok[4:4 + 3 * nv], dtype=float).reshape(nv, 3)
    f = np.array(tok[4 + 3 * nv:4 + 3 * nv + 4 * nf], dtype=np.int64).reshape(nf, 4)
    if (f[:, 0] != 3).any():
        sys.exit('mesh_metrics: %s: not all triangles' % path)
    return v, f[:, 1:]


def evaluate(tool, implicit, points):
    out = subprocess.run([tool, '-q', implicit, '-', '--allow-outside'], check=True, capture_output=True, text=True,
                         input='\n'.join('%.17g %.17g %.17g' % tuple(c) for c in points) + '\n').stdout
    return np.array(out.split(), dtype=float)


def voxel(implicit):  # the smallest spacing
    hdr = open(implicit, 'rb').read(4096).decode('latin-1')
    sp = re.search(r'spacings:\s*([0-9.eE+-]+)\s+([0-9.eE+-]+)\s+([0-9.eE+-]+)', hdr)
    if sp:
        return min(float(s) for s in sp.groups())
    vecs = re.search(r'space directions:([^\n]*)', hdr).group(1)  # (a b c) (d e f) (g h i)
    return min(np.linalg.norm(np.array(g.split(','), dtype=float)) for g in re.findall(r'\(([^)]*)\)', vecs))


def sampled(mesh, implicit, tool):
    v, t = read_off(mesh)
    p = v[t]
    bary = [(i / 4, j / 4, (4 - i - j) / 4) for i in range(5) for j in range(5 - i)]
    pts = np.concatenate([p[:, 0] * a + p[:, 1] * b + p[:, 2] * c for a, b, c in bary])
    f = np.abs(evaluate(tool, implicit, pts)).reshape(len(bary), -1).max(axis=0) / voxel(implicit)
    print(len(t), '%.3f' % f.max(), '%.3f' % np.percentile(f, 99), '%.4f' % f.mean())


def main():
    mesh, implicit, tool = sys.argv[1:4]
    if sys.argv[4:] == ['--sampled']:
        return sampled(mesh, implicit, tool)
    v, t = read_off(mesh)
    p = v[t]  # (n, 3, 3)
    ang = []
    for k in range(3):
        a = p[:, (k + 1) % 3] - p[:, k]
        b = p[:, (k + 2) % 3] - p[:, k]
        c = np.einsum('ij,ij->i', a, b) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
        ang.append(np.degrees(np.arccos(np.clip(c, -1, 1))))
    min_angle = float(np.min(ang))
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    n /= np.linalg.norm(n, axis=1)[:, None]
    # Edge-adjacent pairs: sort the undirected edges, pair equal neighbours.
    e = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    tri = np.tile(np.arange(len(t)), 3)
    e.sort(axis=1)
    key = e[:, 0] * (len(v) + 1) + e[:, 1]
    order = np.argsort(key, kind='stable')
    key, tri = key[order], tri[order]
    cnt = np.bincount(np.unique(key, return_inverse=True)[1])
    first = np.concatenate([[0], np.cumsum(cnt)[:-1]])
    two = first[cnt == 2]
    d = np.einsum('ij,ij->i', n[tri[two]], n[tri[two + 1]])
    jump = float(np.degrees(np.arccos(np.clip(d.min(), -1, 1)))) if len(d) else 0.0
    fvals = evaluate(tool, implicit, p.mean(axis=1))  # at the centroids
    print(len(t), '%.2f' % min_angle, '%.1f' % jump, '%.3f' % (np.nanmax(np.abs(fvals)) / voxel(implicit)))


main()
