#!/usr/bin/env python3
"""Independent checks of a surface mesh (python3 stdlib only, no imgmesh code).

  surface_check.py MESH [WC.nrrd] [--roughness G] [--normals] [--within-voxel]

MESH is OFF or PLY (ascii or binary little endian). Always: every edge in
exactly two triangles, once each way (closed, oriented), and a positive
signed volume (outward). --roughness G: the angle between the normals of
the two triangles of every edge is at most G (implicit2mesh's SMOOTH).
--normals: the PLY's vertex normals are unit and on the outer side of the
triangles around them. With WC (a well-composed NRRD, foreground nonzero),
in its index space (from the header's origin and space directions): each
mesh component's box lies within one voxel of the box of a foreground
component's voxel centres, and each foreground component's box holds a mesh
component; --within-voxel: every vertex within one voxel of a voxel face
(between a foreground and a background voxel). Prints one line; exit 1 with
the reasons when a check fails.
"""
import gzip, math, re, struct, sys


def read_mesh(path):
    raw = open(path, 'rb').read()
    if raw.startswith(b'ply'):
        end = raw.index(b'end_header\n') + 11
        head = raw[:end].decode().split('\n')
        fmt = head[1].split()[1]
        nv = int(next(l for l in head if l.startswith('element vertex')).split()[2])
        nf = int(next(l for l in head if l.startswith('element face')).split()[2])
        # Properties per element: the vertex's floats; the face's list, then
        # int properties (component id, label) after it.
        element, props, face_ints = None, [], 0
        for l in head:
            w = l.split()
            if w[:1] == ['element']:
                element = w[1]
            elif w[:1] == ['property'] and element == 'vertex':
                props.append(w[-1])
            elif w[:1] == ['property'] and element == 'face' and 'list' not in w:
                assert w[1] in ('int', 'int32'), 'face property %s' % w[1]
                face_ints += 1
        if fmt == 'ascii':
            rows = raw[end:].decode().split('\n')
            V = [tuple(map(float, r.split())) for r in rows[:nv]]
            F = [tuple(map(int, r.split()[1:4])) for r in rows[nv:nv + nf]]
        else:
            assert fmt == 'binary_little_endian', fmt
            k = len(props)
            V = [struct.unpack_from('<%df' % k, raw, end + 4 * k * i) for i in range(nv)]
            at = end + 4 * k * nv
            F = []
            for _ in range(nf):
                assert raw[at] == 3, 'not a triangle'
                F.append(struct.unpack_from('<3i', raw, at + 1))
                at += 13 + 4 * face_ints
            assert at == len(raw), 'trailing bytes'
        return [v[:3] for v in V], F, ([v[3:6] for v in V] if 'nx' in props else None)
    words = [w for l in raw.decode().split('\n') for w in l.split('#')[0].split()]
    assert words[0] == 'OFF', 'not OFF or PLY'
    nv, nf = int(words[1]), int(words[2])
    V = [tuple(map(float, words[4 + 3 * i:7 + 3 * i])) for i in range(nv)]
    at, F = 4 + 3 * nv, []
    for _ in range(nf):
        assert words[at] == '3', 'not a triangle'
        F.append(tuple(map(int, words[at + 1:at + 4])))
        at += 4
    return V, F, None


def read_nrrd(path):
    raw = open(path, 'rb').read()
    end = raw.index(b'\n\n')
    hdr = {}
    for line in raw[:end].decode().split('\n')[1:]:
        if ':' in line and not line.startswith('#') and ':=' not in line:
            k, v = line.split(':', 1)
            hdr[k.strip()] = v.strip()
    n = [int(x) for x in hdr['sizes'].split()]
    assert len(n) == 3 and hdr['type'] in ('uint8', 'unsigned char', 'uchar'), hdr['type']
    body = raw[end + 2:]
    if hdr.get('encoding') == 'gzip':
        body = gzip.decompress(body)
    vec = lambda s: [float(x) for x in s.strip('()').split(',')]
    dirs = [vec(v) for v in re.findall(r'\([^)]*\)', hdr['space directions'])]
    origin = vec(hdr.get('space origin', '(0,0,0)'))
    return n, body[:n[0] * n[1] * n[2]], dirs, origin


def inverse3(c):  # c: the three column vectors; returns rows of the inverse
    a = [[c[j][i] for j in range(3)] for i in range(3)]
    det = (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
           + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))
    cof = lambda i, j: ((a[(j + 1) % 3][(i + 1) % 3] * a[(j + 2) % 3][(i + 2) % 3])
                        - (a[(j + 1) % 3][(i + 2) % 3] * a[(j + 2) % 3][(i + 1) % 3]))
    return [[cof(i, j) / det for j in range(3)] for i in range(3)]


def foreground_components(n, body):
    """Boxes (min index, max index) of the 6-connected foreground components, from runs along x."""
    nx, ny, nz = n
    parent, box, runs = [], [], {}
    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i
    zero = b'\0'
    for z in range(nz):
        for y in range(ny):
            row = body[nx * (y + ny * z):nx * (y + 1 + ny * z)]
            x, here = 0, []
            while True:
                while x < nx and row[x] == 0: x += 1
                if x >= nx: break
                e = row.find(zero, x)
                e = nx if e < 0 else e
                k = len(parent); parent.append(k); box.append([x, y, z, e - 1, y, z]); here.append((x, e - 1, k))
                for key in ((y - 1, z), (y, z - 1)):
                    for a, b, j in runs.get(key, ()):
                        if a <= e - 1 and x <= b:
                            ri, rj = find(k), find(j)
                            if ri != rj: parent[ri] = rj
                x = e
            runs[(y, z)] = here
        for y in range(ny): runs.pop((y, z - 1), None)
    comps = {}
    for k in range(len(parent)):
        r, b = find(k), box[k]
        c = comps.setdefault(r, list(b))
        for a in range(3):
            c[a] = min(c[a], b[a]); c[3 + a] = max(c[3 + a], b[3 + a])
    return list(comps.values())


def main(argv):
    args = [a for a in argv if not a.startswith('--')]
    opt = lambda k: argv[argv.index(k) + 1] if k in argv else None
    rough = opt('--roughness')
    if rough: args.remove(rough)
    V, F, N = read_mesh(args[0])
    bad = []
    if not F: bad.append('no triangle')
    # Closed and oriented: each directed edge once, its reverse once.
    edge = {}
    for t, (a, b, c) in enumerate(F):
        for e in ((a, b), (b, c), (c, a)):
            if e in edge: bad.append('edge %s in two triangles the same way' % (e,)); break
            edge[e] = t
    open_edges = sum(1 for (a, b) in edge if (b, a) not in edge)
    if open_edges: bad.append('%d edges without a reverse (not closed or not oriented)' % open_edges)
    def normal(t):
        p, q, r = (V[i] for i in F[t])
        u = [q[m] - p[m] for m in range(3)]; w = [r[m] - p[m] for m in range(3)]
        return (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
    NF = [normal(t) for t in range(len(F))]
    volume = sum(V[a][0] * (V[b][1] * V[c][2] - V[b][2] * V[c][1]) - V[a][1] * (V[b][0] * V[c][2] - V[b][2] * V[c][0])
                 + V[a][2] * (V[b][0] * V[c][1] - V[b][1] * V[c][0]) for a, b, c in F) / 6
    if not volume > 0: bad.append('signed volume %g not positive (inward)' % volume)
    worst = 0.0
    for (a, b), t in edge.items():
        s = edge.get((b, a))
        if s is None or a > b: continue
        n, m = NF[t], NF[s]
        ln, lm = math.sqrt(sum(x * x for x in n)), math.sqrt(sum(x * x for x in m))
        if ln == 0 or lm == 0: bad.append('a degenerate triangle'); continue
        worst = max(worst, math.acos(max(-1.0, min(1.0, sum(n[i] * m[i] for i in range(3)) / (ln * lm)))))
    # The file holds float coordinates: allow for their rounding.
    if rough is not None and worst > float(rough) + 1e-4:
        bad.append('roughness %.6f rad above %s' % (worst, rough))
    if '--normals' in argv:
        if N is None: bad.append('no vertex normals')
        else:
            acc = [[0.0] * 3 for _ in V]
            for t, tri in enumerate(F):
                for v in tri:
                    for m in range(3): acc[v][m] += NF[t][m]
            off = sum(1 for n in N if abs(math.sqrt(sum(x * x for x in n)) - 1) > 1e-5)
            inward = sum(1 for n, a in zip(N, acc) if sum(n[m] * a[m] for m in range(3)) <= 0)
            if off: bad.append('%d normals not unit' % off)
            if inward: bad.append('%d of %d normals point inward' % (inward, len(N)))
    line = 'triangles %d volume %.6g roughness %.6f' % (len(F), volume, worst)
    if len(args) > 1:
        n, body, dirs, origin = read_nrrd(args[1])
        inv = inverse3(dirs)
        idx = [[sum(inv[i][j] * (p[j] - origin[j]) for j in range(3)) for i in range(3)] for p in V]
        # Mesh components by shared vertices.
        parent = list(range(len(V)))
        def find(i):
            while parent[i] != i:
                parent[i] = parent[parent[i]]; i = parent[i]
            return i
        for a, b, c in F:
            for u in (b, c):
                ru, ra = find(u), find(a)
                if ru != ra: parent[ru] = ra
        mboxes = {}
        for tri in F:
            for v in tri:
                bx = mboxes.setdefault(find(v), [math.inf] * 3 + [-math.inf] * 3)
                for a in range(3):
                    bx[a] = min(bx[a], idx[v][a]); bx[3 + a] = max(bx[3 + a], idx[v][a])
        vboxes = foreground_components(n, body)
        inside = lambda m, c: all(c[a] - 1 - 1e-6 <= m[a] and m[3 + a] <= c[3 + a] + 1 + 1e-6 for a in range(3))
        lost = sum(1 for m in mboxes.values() if not any(inside(m, c) for c in vboxes))
        empty = sum(1 for c in vboxes if not any(inside(m, c) for m in mboxes.values()))
        if lost: bad.append('%d of %d mesh components outside every foreground component\'s box' % (lost, len(mboxes)))
        if empty: bad.append('%d of %d foreground components without a mesh component in their box' % (empty, len(vboxes)))
        line += ' components %d foreground_components %d' % (len(mboxes), len(vboxes))
        if '--within-voxel' in argv:
            at = lambda i, j, k: 0 <= i < n[0] and 0 <= j < n[1] and 0 <= k < n[2] and body[i + n[0] * (j + n[1] * k)] != 0
            far = 0
            for p in idx:
                # Some voxel face between a foreground and a background voxel
                # within one voxel (per axis) of p: look at the centres around.
                c = [int(math.floor(x)) for x in p]
                cells = [(i, j, k) for i in range(c[0] - 1, c[0] + 3) for j in range(c[1] - 1, c[1] + 3)
                         for k in range(c[2] - 1, c[2] + 3)]
                # The face between q and q + d is the unit square at q + d/2.
                def face_near(q, d):
                    return all((abs(p[a] - q[a] - d[a] / 2) if d[a] else max(0.0, abs(p[a] - q[a]) - 0.5)) <= 1 + 1e-9
                               for a in range(3))
                ok = any(face_near(q, d) and not at(q[0] + d[0], q[1] + d[1], q[2] + d[2])
                         for q in cells if at(*q)
                         for d in ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)))
                far += not ok
            if far: bad.append('%d of %d vertices farther than a voxel from the voxel faces' % (far, len(V)))
    print(line)
    if bad:
        print('surface_check.py: ' + '; '.join(bad[:5]), file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
