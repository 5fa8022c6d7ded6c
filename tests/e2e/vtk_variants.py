"""vtk_variants.py SURFACE.vtp: the surface (read by VTK) and a grid of
tetrahedra written by VTK's own writers in the layouts they offer, each
file's counts as VTK holds them printed as a line "FILE POINTS CELLS",
for a tetrahedral file then its volume by region "R:V ...".

XML (vtkXMLPolyDataWriter, vtkXMLUnstructuredGridWriter): the defaults
(appended base64 data, zlib, UInt32 header), ASCII, inline binary, appended
raw or base64, compressed or not, UInt32 or UInt64 headers, Int32 or Int64
ids, little- or big-endian; legacy (vtkPolyDataWriter,
vtkUnstructuredGridWriter) ASCII and binary, file versions 5.1 and 4.2.
Also wrong.vtp: the defaults with the first triangle's label pair swapped,
and lz4.vtp, lzma.vtp (compressors imgmesh does not decode). Run by a
python with VTK 9 (Debian's python3-vtk9)."""
import itertools, sys
import vtk

src = vtk.vtkXMLPolyDataReader()
src.SetFileName(sys.argv[1])
src.Update()
surface = src.GetOutput()


# A 12 x 12 x 12 grid of cubes, each cut into the 6 tetrahedra around its
# diagonal (Kuhn: conforming), positively oriented; region 1 for x < 6, else
# 2. Coordinates scaled so that they are not integers.
def grid():
    n, h = 12, (0.7, 1.1, 1.3)
    g = vtk.vtkUnstructuredGrid()
    pts = vtk.vtkPoints()
    pts.SetDataTypeToDouble()
    for k, j, i in itertools.product(range(n + 1), repeat=3):
        pts.InsertNextPoint(i * h[0] + 0.1, j * h[1] - 0.2, k * h[2] + 0.3)
    g.SetPoints(pts)
    region = vtk.vtkIntArray()
    region.SetName('region')
    vid = lambda i, j, k: (k * (n + 1) + j) * (n + 1) + i
    volume = {1: 0.0, 2: 0.0}
    for k, j, i in itertools.product(range(n), repeat=3):
        for perm in itertools.permutations(range(3)):
            c, corners = [i, j, k], [vid(i, j, k)]
            for axis in perm:
                c[axis] += 1
                corners.append(vid(*c))
            odd = sum(perm[a] > perm[b] for a in range(3) for b in range(a + 1, 3)) % 2
            if odd:
                corners[1], corners[2] = corners[2], corners[1]
            ids = vtk.vtkIdList()
            for v in corners:
                ids.InsertNextId(v)
            g.InsertNextCell(vtk.VTK_TETRA, ids)
            r = 1 if i < n // 2 else 2
            region.InsertNextValue(r)
            volume[r] += h[0] * h[1] * h[2] / 6
    g.GetCellData().AddArray(region)
    return g, volume


def xml(data, name, mode='appended', base64=True, compressor='zlib', header=32, ids=64, order='little'):
    w = vtk.vtkXMLPolyDataWriter() if name.endswith('.vtp') else vtk.vtkXMLUnstructuredGridWriter()
    w.SetInputData(data)
    w.SetFileName(name)
    {'ascii': w.SetDataModeToAscii, 'binary': w.SetDataModeToBinary, 'appended': w.SetDataModeToAppended}[mode]()
    w.SetEncodeAppendedData(base64)
    {'none': w.SetCompressorTypeToNone, 'zlib': w.SetCompressorTypeToZLib, 'lz4': w.SetCompressorTypeToLZ4,
     'lzma': w.SetCompressorTypeToLZMA}[compressor]()
    (w.SetHeaderTypeToUInt32 if header == 32 else w.SetHeaderTypeToUInt64)()
    (w.SetIdTypeToInt32 if ids == 32 else w.SetIdTypeToInt64)()
    (w.SetByteOrderToLittleEndian if order == 'little' else w.SetByteOrderToBigEndian)()
    assert w.Write() == 1, name
    return name


def legacy(data, name, binary, version):
    w = vtk.vtkPolyDataWriter() if 'surface' in name else vtk.vtkUnstructuredGridWriter()
    w.SetInputData(data)
    w.SetFileName(name)
    (w.SetFileTypeToBinary if binary else w.SetFileTypeToASCII)()
    if version == 42:
        w.SetFileVersion(42)
    assert w.Write() == 1, name
    return name


def written(data, ext, legacy_name):
    default = vtk.vtkXMLPolyDataWriter() if ext == 'vtp' else vtk.vtkXMLUnstructuredGridWriter()
    default.SetInputData(data)
    default.SetFileName('default.' + ext)
    assert default.Write() == 1
    return [
        'default.' + ext,
        xml(data, 'ascii.' + ext, mode='ascii', ids=32),
        xml(data, 'inline-zlib-h64-be.' + ext, mode='binary', header=64, order='big'),
        xml(data, 'inline-none-h32-id32.' + ext, mode='binary', compressor='none', ids=32),
        xml(data, 'appended-raw-none-h32-id32.' + ext, base64=False, compressor='none', ids=32),
        xml(data, 'appended-raw-zlib-h64-be.' + ext, base64=False, header=64, order='big'),
        xml(data, 'appended-b64-none-h64-be.' + ext, compressor='none', header=64, order='big'),
        xml(data, 'appended-b64-zlib-h64-id32.' + ext, header=64, ids=32),
        legacy(data, legacy_name + '-ascii-5.1.vtk', False, 51),
        legacy(data, legacy_name + '-binary-5.1.vtk', True, 51),
        legacy(data, legacy_name + '-ascii-4.2.vtk', False, 42),
        legacy(data, legacy_name + '-binary-4.2.vtk', True, 42),
    ]


for f in written(surface, 'vtp', 'surface'):
    print(f, surface.GetNumberOfPoints(), surface.GetNumberOfPolys())
tets, volume = grid()
for f in written(tets, 'vtu', 'tets'):
    print(f, tets.GetNumberOfPoints(), tets.GetNumberOfCells(), ' '.join('%d:%.17g' % rv for rv in volume.items()))
xml(surface, 'lz4.vtp', compressor='lz4')
xml(surface, 'lzma.vtp', compressor='lzma')
labels = surface.GetCellData().GetArray('labels')
a, b = labels.GetTuple2(0)
labels.SetTuple2(0, b, a)
default = vtk.vtkXMLPolyDataWriter()
default.SetInputData(surface)
default.SetFileName('wrong.vtp')
assert default.Write() == 1
