"""surface_compare.py REF.off [--labels FILE] OUT[:READER[:TOL]]...: each
OUT (any format imgmesh writes, read by surface_read with READER, default
text) holds REF's vertices (within TOL, relative to the bounding box;
default 1e-12), its triangles with their
winding, per face a component id that numbers the connected components
(faces sharing a vertex) 0.. by decreasing size; with LABELS (a file of one
label a face, as REF's faces) the labels; unit outward normals if present;
for .msh a physical group per label or component named so."""
import math, sys
sys.path.insert(0, __import__('os').path.dirname(__file__))
import surface_read

def check(ref, path, reader, tol, labels):
    out = surface_read.read(path, reader)
    fail = lambda msg: sys.exit('%s: %s' % (path, msg))

    P, T = ref['points'], ref['triangles']
    lo = [min(p[a] for p in P) for a in range(3)]
    hi = [max(p[a] for p in P) for a in range(3)]
    scale = max(h - l for h, l in zip(hi, lo))
    if len(out['points']) != len(P): fail('%d vertices, want %d' % (len(out['points']), len(P)))
    worst = max(abs(a - b) for p, q in zip(P, out['points']) for a, b in zip(p, q))
    if worst > tol * scale:
        # A reader may renumber the vertices (meshio orders .msh 4.1 nodes by
        # entity): then every vertex must be one of REF's, exactly.
        at = {tuple(p): i for i, p in enumerate(P)}
        if tol > 1e-12 or any(tuple(q) not in at for q in out['points']):
            fail('a vertex moved by %g (bounding box %g)' % (worst, scale))
        new = [at[tuple(q)] for q in out['points']]
        out['triangles'] = [tuple(new[v] for v in t) for t in out['triangles']]
        if out['normals'] is not None:
            normals = [None] * len(P)
            for i, n in zip(new, out['normals']): normals[i] = n
            out['normals'] = normals
    # The same triangles with the same winding; .msh 4.1 groups them by entity,
    # so faces are matched by their vertices (rotated, never flipped) and the
    # per-face data put in REF's order.
    canon = lambda t: min((t[i], t[(i + 1) % 3], t[(i + 2) % 3]) for i in range(3))
    where = {canon(t): i for i, t in enumerate(out['triangles'])}
    if len(where) != len(T) or any(canon(t) not in where for t in T): fail('triangles or their winding differ')
    order = [where[canon(t)] for t in T]
    for key in ('component', 'label', 'physical'):
        if out[key] is not None: out[key] = [out[key][i] for i in order]

    # Components: union of faces sharing a vertex.
    parent = list(range(len(P)))
    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x
    for t in T:
        for v in t[1:]:
            parent[find(v)] = find(t[0])
    comp = out['component']
    if comp is None or len(comp) != len(T): fail('no component id per face')
    pairs = {(find(t[0]), c) for t, c in zip(T, comp)}
    roots = {r for r, _ in pairs}
    if len(pairs) != len(roots) or len({c for _, c in pairs}) != len(roots): fail('component ids do not number the components')
    sizes = [comp.count(c) for c in range(len(roots))]
    if sorted(set(comp)) != list(range(len(roots))) or sizes != sorted(sizes, reverse=True):
        fail('component ids not 0.. by decreasing size: %s' % sizes)

    if labels is not None:
        if out['label'] is not None and list(out['label']) != labels: fail('labels differ')
        if out['label'] is None and out['physical'] is None: fail('no labels')

    if out['physical'] is not None:
        names = out.get('names', {})
        for i, (p, c) in enumerate(zip(out['physical'], comp)):
            want = labels[i] if labels is not None else c + 1
            if p != want: fail('face %d in physical group %d, want %d' % (i, p, want))
        for p in set(out['physical']):
            want = 'label %d' % p if labels is not None else 'component %d' % (p - 1)
            if names and names.get(p) != want: fail('physical group %d named %r' % (p, names.get(p)))

    if out['normals'] is not None:
        around = [[0.0, 0.0, 0.0] for _ in P]
        for a, b, c in T:
            u = [P[b][k] - P[a][k] for k in range(3)]
            w = [P[c][k] - P[a][k] for k in range(3)]
            n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
            for v in (a, b, c):
                for k in range(3):
                    around[v][k] += n[k]
        for n, s in zip(out['normals'], around):
            if abs(math.sqrt(sum(x * x for x in n)) - 1) > 1e-3: fail('a normal is not unit')
            if sum(x * y for x, y in zip(n, s)) <= 0: fail('a normal points inward')
    print('%s: %d vertices, %d triangles, %d components%s' % (path, len(P), len(T), len(roots),
          ', normals' if out['normals'] else ''))


args = sys.argv[1:]
ref = surface_read.read(args.pop(0))
labels = None
if args[0] == '--labels':
    labels = [int(l) for l in open(args[1])]
    args = args[2:]
for a in args:
    w = a.split(':')
    path, reader, tol = w[0], w[1] if len(w) > 1 else 'text', w[2] if len(w) > 2 else '1e-12'
    check(ref, path, reader, float(tol), labels)
