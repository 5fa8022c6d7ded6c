"""Readers for the surface formats imgmesh writes, independent of its code:
VTK files by VTK's own Python readers, .msh by
meshio (when given; ASCII or binary) or the text grammar of Gmsh's format
documentation, PLY (binary little-endian or ASCII) and OFF by their grammars.
read(path, reader) -> dict(points, triangles, component, label, normals, physical,
pairs); a missing field is None (pairs: each face's (behind, front) labels,
from VTK's 2-component labels or PLY's label_behind and label_front); VTK's field data as names {label: name}.
reader: 'vtk', 'meshio' or 'text'."""
import struct, sys


def read_off(path):
    words = [w for line in open(path) for w in line.split('#')[0].split()]
    assert words[0] == 'OFF'
    nv, nf = int(words[1]), int(words[2])
    it = 4
    pts = [tuple(float(x) for x in words[it + 3 * i:it + 3 * i + 3]) for i in range(nv)]
    it += 3 * nv
    tris = []
    for _ in range(nf):
        assert words[it] == '3'
        tris.append(tuple(int(x) for x in words[it + 1:it + 4]))
        it += 4
    return dict(points=pts, triangles=tris, component=None, label=None, normals=None, physical=None, pairs=None)


def f32(text):
    return struct.unpack('<f', struct.pack('<f', float(text)))[0]


def read_ply(path):
    b = open(path, 'rb').read()
    end = b.index(b'end_header\n') + len(b'end_header\n')
    head = b[:end].decode().splitlines()
    assert head[0] == 'ply' and head[1] in ('format binary_little_endian 1.0', 'format ascii 1.0'), head[:2]
    ascii = head[1] == 'format ascii 1.0'
    words = b[end:].split() if ascii else None
    elements, cur = [], None
    for line in head:
        w = line.split()
        if w[0] == 'element':
            cur = (w[1], int(w[2]), [])
            elements.append(cur)
        elif w[0] == 'property':
            cur[2].append(w[1:])
    fmt = {'float': 'f', 'double': 'd', 'int': 'i', 'uchar': 'B', 'uint': 'I'}
    off, out = end, {}
    for name, n, props in elements:
        rows = []
        for _ in range(n):
            row = {}
            for p in props:
                if ascii:
                    kind = p[-2 if p[0] != 'list' else 2]
                    # A float property is a float32 however its text is written.
                    cast = (f32 if kind in ('float', 'float32') else float) if kind in ('float', 'float32', 'double', 'float64') else int
                    if p[0] == 'list':
                        k = int(words[0])
                        row[p[3]] = tuple(cast(x) for x in words[1:1 + k])
                        words = words[1 + k:]
                    else:
                        row[p[1]] = cast(words[0])
                        words = words[1:]
                elif p[0] == 'list':
                    (k,) = struct.unpack_from('<' + fmt[p[1]], b, off)
                    off += struct.calcsize(fmt[p[1]])
                    row[p[3]] = struct.unpack_from('<%d%s' % (k, fmt[p[2]]), b, off)
                    off += k * struct.calcsize(fmt[p[2]])
                else:
                    (row[p[1]],) = struct.unpack_from('<' + fmt[p[0]], b, off)
                    off += struct.calcsize(fmt[p[0]])
            rows.append(row)
        out[name] = rows
    assert (not words) if ascii else off == len(b), 'trailing bytes'
    v, f = out['vertex'], out['face']
    return dict(points=[(r['x'], r['y'], r['z']) for r in v],
                triangles=[tuple(r['vertex_indices']) for r in f],
                component=[r['component'] for r in f] if f and 'component' in f[0] else None,
                label=[r['label'] for r in f] if f and 'label' in f[0] else None,
                normals=[(r['nx'], r['ny'], r['nz']) for r in v] if v and 'nx' in v[0] else None,
                physical=None,
                pairs=[(r['label_behind'], r['label_front']) for r in f] if f and 'label_behind' in f[0] else None)


def read_vtk(path):
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    r = vtk.vtkXMLPolyDataReader() if path.endswith('.vtp') else vtk.vtkPolyDataReader()
    if path.endswith('.vtk'):  # every array, not only the first SCALARS
        r.ReadAllScalarsOn()
        r.ReadAllNormalsOn()
        r.ReadAllFieldsOn()
    r.SetFileName(path)
    r.Update()
    pd = r.GetOutput()
    assert pd.GetNumberOfPoints() > 0, 'VTK read no points'
    pts = [tuple(p) for p in vtk_to_numpy(pd.GetPoints().GetData()).tolist()]
    tris = []
    for i in range(pd.GetNumberOfCells()):
        c = pd.GetCell(i)
        assert c.GetNumberOfPoints() == 3
        tris.append(tuple(c.GetPointId(k) for k in range(3)))
    arr = lambda a: None if a is None else vtk_to_numpy(a).tolist()
    n = pd.GetPointData().GetNormals()
    fd = pd.GetFieldData()
    values, strings = fd.GetAbstractArray('label_values'), fd.GetAbstractArray('label_names')
    names = None
    if values is not None and strings is not None:
        names = {int(values.GetValue(i)): strings.GetValue(i) for i in range(values.GetNumberOfTuples())}
    pairs = pd.GetCellData().GetArray('labels')
    if pairs is not None:
        assert pairs.GetNumberOfComponents() == 2, 'labels of %d components' % pairs.GetNumberOfComponents()
        pairs = [tuple(int(x) for x in p) for p in vtk_to_numpy(pairs).tolist()]
    return dict(points=pts, triangles=tris, component=arr(pd.GetCellData().GetArray('component')),
                label=arr(pd.GetCellData().GetArray('label')),
                normals=None if n is None else [tuple(x) for x in arr(n)], physical=None, names=names,
                pairs=pairs)


def read_msh_meshio(path):
    import meshio
    m = meshio.read(path)
    tris, phys, geo = [], [], []
    for block, p, g in zip(m.cells, m.cell_data['gmsh:physical'], m.cell_data['gmsh:geometrical']):
        assert block.type == 'triangle'
        tris += [tuple(int(x) for x in t) for t in block.data]
        phys += [int(x) for x in p]
        geo += [int(x) for x in g]
    n = m.point_data.get('normals')
    return dict(points=[tuple(p) for p in m.points.tolist()], triangles=tris, component=[g - 1 for g in geo],
                label=None, normals=None if n is None else [tuple(x) for x in n.tolist()], physical=phys,
                names={v[0]: k for k, v in m.field_data.items()}, pairs=None)


def read_msh_text(path):
    lines = [l.strip() for l in open(path)]
    sec = {}
    i = 0
    while i < len(lines):
        if lines[i].startswith('$') and not lines[i].startswith('$End'):
            name = lines[i][1:]
            j = lines.index('$End' + name, i)
            sec.setdefault(name, []).append(lines[i + 1:j])
            i = j
        i += 1
    version = sec['MeshFormat'][0][0].split()[0]
    names = {}
    for l in sec.get('PhysicalNames', [[]])[0][1:]:
        w = l.split(None, 2)
        names[int(w[1])] = w[2].strip('"')
    nodes, tris, phys, geo = {}, [], [], []
    if version.startswith('2'):
        for l in sec['Nodes'][0][1:]:
            w = l.split()
            nodes[int(w[0])] = tuple(float(x) for x in w[1:4])
        for l in sec['Elements'][0][1:]:
            w = [int(x) for x in l.split()]
            if w[1] != 2:
                continue
            nt = w[2]
            phys.append(w[3])
            geo.append(w[4])
            tris.append(tuple(w[3 + nt:6 + nt]))
    else:
        ent = {}
        e = sec['Entities'][0]
        np_, nc, ns, _ = (int(x) for x in e[0].split())
        for l in e[1 + np_ + nc:1 + np_ + nc + ns]:
            w = l.split()
            k = int(w[7])
            ent[int(w[0])] = [int(x) for x in w[8:8 + k]]
        body, k = sec['Nodes'][0], 1
        while k < len(body):
            dim, tag, par, n = (int(x) for x in body[k].split())
            ids = [int(x) for x in body[k + 1:k + 1 + n]]
            for t, l in zip(ids, body[k + 1 + n:k + 1 + 2 * n]):
                nodes[t] = tuple(float(x) for x in l.split())
            k += 1 + 2 * n
        body, k = sec['Elements'][0], 1
        while k < len(body):
            dim, tag, typ, n = (int(x) for x in body[k].split())
            for l in body[k + 1:k + 1 + n]:
                if typ == 2:
                    w = [int(x) for x in l.split()]
                    tris.append(tuple(w[1:4]))
                    phys.append(ent[tag][0])
                    geo.append(tag)
            k += 1 + n
    order = sorted(nodes)
    index = {t: i for i, t in enumerate(order)}
    normals = None
    for view in sec.get('NodeData', []):
        n = int(view[7])
        vals = {int(l.split()[0]): tuple(float(x) for x in l.split()[1:4]) for l in view[8:8 + n]}
        normals = [vals[t] for t in order]
    return dict(points=[nodes[t] for t in order], triangles=[tuple(index[v] for v in t) for t in tris],
                component=[g - 1 for g in geo], label=None, normals=normals, physical=phys, names=names, pairs=None)


def read(path, reader='text'):
    if path.endswith('.off'):
        return read_off(path)
    if path.endswith('.ply'):
        return read_ply(path)
    if path.endswith(('.vtp', '.vtk')):
        return read_vtk(path)
    if path.endswith('.msh'):
        return read_msh_meshio(path) if reader == 'meshio' else read_msh_text(path)
    raise ValueError(path)


if __name__ == '__main__':
    m = read(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else 'text')
    print(len(m['points']), len(m['triangles']))
