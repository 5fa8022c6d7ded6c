#!/usr/bin/env bash
# World coordinates through the 3D pipeline, img2wc | wc2implicit |
# implicit2mesh, under a non-symmetric direction matrix with anisotropic
# spacing: the direction vectors are R diag(0.6, 0.9, 1.4), R a rotation by
# 40 degrees about (1, 2, 3) (R != R^T, so a D / D^T or a row / column
# mix-up moves the mesh). The input is an asymmetric L-shaped block touching
# the grid's low x and y sides and its high z side. Every expectation is
# computed here from the input's header alone (world = origin + D index).
# The mesh is asked for fidelity, --max-distance a quarter of the smallest
# step: the default bounds leave coarse triangles that cut voxel corners.
source "$(dirname "$0")/lib.sh"
SURF=$E2E/surface_check.py

# geometry.py: the input, and world points of its voxel centres.
geometry() {
  cat > geometry.py <<'PY'
import math, re, sys
N = (9, 8, 6)
def rotation(axis, deg):
    l = math.sqrt(sum(a * a for a in axis)); x, y, z = (a / l for a in axis)
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg)); C = 1 - c
    return [[c + x * x * C, x * y * C - z * s, x * z * C + y * s],
            [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
            [z * x * C - y * s, z * y * C + x * s, c + z * z * C]]
R = rotation((1, 2, 3), 40)
SPACING = (0.6, 0.9, 1.4)
D = [[R[r][c] * SPACING[c] for c in range(3)] for r in range(3)]  # column c: axis c's step
ORIGIN = (5.0, -3.0, 7.0)
def inside(i, j, k):  # the L: a long arm along x, a short one along y; z from 3 to the top
    return k >= 3 and ((i <= 5 and j <= 2) or (i <= 1 and j <= 5))
def world(i, j, k, o=ORIGIN):
    return [o[r] + D[r][0] * i + D[r][1] * j + D[r][2] * k for r in range(3)]
def header(path):
    raw = open(path, 'rb').read(); end = raw.index(b'\n\n')
    h = dict(l.split(':', 1) for l in raw[:end].decode().split('\n')[1:] if ':' in l and not l.startswith('#') and ':=' not in l)
    vec = lambda s: [float(x) for x in s.strip(' ()').split(',')]
    return ([int(x) for x in h['sizes'].split()], [vec(v) for v in re.findall(r'\([^)]*\)', h['space directions'])],
            vec(h['space origin']))
if __name__ == '__main__':
    what = sys.argv[1]
    if what == 'image':
        body = bytes(1 if inside(i, j, k) else 0 for k in range(N[2]) for j in range(N[1]) for i in range(N[0]))
        dirs = ' '.join('(%r,%r,%r)' % tuple(D[r][c] for r in range(3)) for c in range(3))
        open('l.nrrd', 'wb').write(('NRRD0004\ntype: uint8\ndimension: 3\nspace: left-posterior-superior\n'
            'sizes: %d %d %d\nspace directions: %s\nspace origin: (%r,%r,%r)\nencoding: raw\n\n'
            % (N + (dirs,) + ORIGIN)).encode() + body)
    elif what == 'centres':  # x y z winding: every voxel centre, 1 inside the L, 0 outside
        for k in range(N[2]):
            for j in range(N[1]):
                for i in range(N[0]):
                    print('%.17g %.17g %.17g' % tuple(world(i, j, k)), int(inside(i, j, k)))
PY
}
chain() {
  geometry && python3 geometry.py image &&
    expect 0 img2wc l.nrrd l-wc.nrrd && expect 0 wc2implicit l-wc.nrrd l-f.nrrd &&
    expect 0 implicit2mesh l-f.nrrd l.ply --normals --max-distance 0.15
}
inputs_here() { local d; d=$(dirname "$(shared l.ply chain)"); cp "$d"/{geometry.py,l.nrrd,l-wc.nrrd,l-f.nrrd,l.ply} .; }

# The grid grows by one voxel on the three sides the L touches; the origin
# moves by one step back along x and along y (not z: its high side grew),
# the direction vectors stay, the voxels stay at their world places.
case_img2wc_pads_and_moves_the_origin_one_step() {
  inputs_here
  python3 - <<'PY' > py.txt 2>&1 || fail "img2wc's output header: $(tail -1 py.txt)"
from geometry import *
n, d, o = header('l-wc.nrrd')
assert n == [N[0] + 1, N[1] + 1, N[2] + 1], n
for c in range(3):
    assert all(abs(d[c][r] - D[r][c]) < 1e-12 for r in range(3)), ('direction', c, d[c])
want = world(-1, -1, 0)
assert all(abs(o[r] - want[r]) < 1e-12 for r in range(3)), ('origin', o, want)
PY
}

# f < 0 at every foreground voxel centre, > 0 at every background one, at
# the world points of the input's header.
case_f_has_the_sign_of_every_voxel_centre() {
  inputs_here
  python3 geometry.py centres > c.txt
  cut -d' ' -f1-3 c.txt > p.txt
  expect 0 implicit-eval l-f.nrrd p.txt -o f.txt
  paste -d' ' c.txt f.txt | awk '($4 == 1) != ($5 < 0) { bad++; if (bad < 4) print }
    END { exit bad > 0 }' > bad.txt || fail "f of the wrong sign at voxel centres: $(head -3 bad.txt)"
}

# The mesh in the scan's frame: every vertex within one voxel of the input's
# voxel faces (in its index space); winding number 1 about foreground
# centres, 0 about background ones; normals unit and outward; volume
# positive; closed and oriented.
case_mesh_in_the_scan_frame_normals_outward() {
  inputs_here
  python3 "$SURF" l.ply l.nrrd --within-voxel --normals > s.txt 2>&1 || fail "$(cat s.txt)"
  python3 geometry.py centres > c.txt
  python3 - l.ply c.txt "$SURF" <<'PY' > w.txt 2>&1 || fail "winding numbers: $(tail -1 w.txt)"
import importlib.util, math, sys
spec = importlib.util.spec_from_file_location('sc', sys.argv[3])
sc = importlib.util.module_from_spec(spec); spec.loader.exec_module(sc)
V, F, _ = sc.read_mesh(sys.argv[1])
def winding(p):  # sum of the triangles' signed solid angles (Van Oosterom-Strackee) / 4 pi
    s = 0.0
    for a, b, c in F:
        A = [V[a][m] - p[m] for m in range(3)]; B = [V[b][m] - p[m] for m in range(3)]; C = [V[c][m] - p[m] for m in range(3)]
        la, lb, lc = (math.sqrt(sum(x * x for x in v)) for v in (A, B, C))
        det = A[0] * (B[1] * C[2] - B[2] * C[1]) - A[1] * (B[0] * C[2] - B[2] * C[0]) + A[2] * (B[0] * C[1] - B[1] * C[0])
        dot = lambda u, v: sum(u[m] * v[m] for m in range(3))
        s += 2 * math.atan2(det, la * lb * lc + dot(A, B) * lc + dot(A, C) * lb + dot(B, C) * la)
    return s / (4 * math.pi)
bad = []
for line in open(sys.argv[2]):
    x, y, z, w = line.split()
    got = winding((float(x), float(y), float(z)))
    if abs(got - int(w)) > 1e-6: bad.append('%s %s %s: %.4f, want %s' % (x, y, z, got, w))
print('%d of %d centres wrong' % (len(bad), sum(1 for _ in open(sys.argv[2]))))
if bad: sys.exit('%d centres with a wrong winding number, e.g. %s' % (len(bad), bad[0]))
PY
}

run_cases "$@"
