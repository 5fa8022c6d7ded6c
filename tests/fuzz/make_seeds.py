#!/usr/bin/env python3
"""Writes the hand-made seeds of tests/fuzz/corpus/<target>/ (run from
anywhere; files found by fuzzing are added beside them by hand, named
crash-*, leak-*, oom-* or timeout-*). Each seed is small: the fuzzer grows
inputs from them. The first byte of a seed is the target's selector (see
each fuzz_<target>.cpp)."""
import base64, gzip, os, struct, zlib

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")
data = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "share", "data")


def put(target, name, content):
    os.makedirs(os.path.join(root, target), exist_ok=True)
    if isinstance(content, str):
        content = content.encode()
    with open(os.path.join(root, target, name), "wb") as f:
        f.write(content)


def nrrd(sizes, typ="uint8", enc="raw", payload=b"", extra=""):
    h = "NRRD0004\ntype: %s\ndimension: %d\nsizes: %s\nencoding: %s\n%s\n" % (
        typ, len(sizes), " ".join(map(str, sizes)), enc, extra)
    return h.encode() + payload


cube = bytes([0] * 13 + [1] + [0] * 13)  # 3x3x3, the centre voxel
# images: selector 0 .nrrd, 1 .mha, 2 .nii, 3 .nii.gz, 4 .png, 5 stdin
put("image", "nrrd-raw", b"\0" + nrrd([3, 3, 3], payload=cube))
put("image", "nrrd-gzip", b"\0" + nrrd([3, 3, 3], enc="gzip", payload=gzip.compress(cube, mtime=0)))
put("image", "nrrd-float", b"\0" + nrrd([2, 2], typ="float", payload=struct.pack("<4f", 0, 1.5, float("nan"), 2)))
put("image", "nrrd-int16-endian", b"\0" + nrrd([2, 2, 1], typ="int16", payload=struct.pack(">4h", 0, 3, -2, 7),
                                             extra="endian: big\nspacings: 0.5 1 2"))
put("image", "nrrd-truncated", b"\0" + nrrd([4, 4, 4], payload=cube))
put("image", "nrrd-huge", b"\0" + nrrd([100000, 100000, 100000], payload=cube))
put("image", "nrrd-huge-gzip", b"\0" + nrrd([60000, 60000, 60], enc="gzip", payload=gzip.compress(cube, mtime=0)))
put("image", "nrrd-ascii", b"\0" + nrrd([2, 2], typ="int", enc="ascii", payload=b"0 1 2 inf\n"))
put("image", "nrrd-stdin", b"\5" + nrrd([3, 3, 3], payload=cube))
mha = "ObjectType = Image\nNDims = 3\nBinaryData = True\nDimSize = 3 3 3\nElementSpacing = 1 1 1\n" \
      "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n"
put("image", "mha-local", b"\1" + mha.encode() + cube)
put("image", "mha-compressed", b"\1" + mha.replace("ElementType", "CompressedData = True\nElementType").encode()
    + zlib.compress(cube))
put("image", "mha-stdin", b"\5" + mha.encode() + cube)


def nifti(dims, datatype=2, bitpix=8, payload=cube, magic=b"n+1\0"):
    h = struct.pack("<i", 348) + b"\0" * 36
    dim = [len(dims)] + list(dims) + [1] * (7 - len(dims))
    h += struct.pack("<8h", *dim) + b"\0" * 14
    h += struct.pack("<hhh", datatype, bitpix, 0)
    h += struct.pack("<8f", 1, 1, 1, 1, 1, 1, 1, 1)
    h += struct.pack("<f", 352.0)  # vox_offset
    h += b"\0" * (344 - len(h)) + magic
    return h + b"\0" * 4 + payload


put("image", "nii", b"\2" + nifti([3, 3, 3]))
put("image", "nii-gz", b"\3" + gzip.compress(nifti([3, 3, 3]), mtime=0))
put("image", "nii-gz-truncated", b"\3" + gzip.compress(nifti([3, 3, 3]), mtime=0)[:-12])
put("image", "nii-huge", b"\2" + nifti([30000, 30000, 30000]))
put("image", "nii-stdin", b"\5" + nifti([3, 3, 3]))
with open(os.path.join(data, "BinaryImage.png"), "rb") as f:
    put("image", "png", b"\4" + f.read())


def png(w, h, rows):
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    raw = b"".join(b"\0" + r for r in rows)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0)) + \
        chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


put("image", "png-tiny", b"\4" + png(2, 2, [b"\0\xff", b"\xff\0"]))
put("image", "png-huge", b"\4" + png(1 << 20, 1 << 20, [b"\0\xff"]))

# implicit function files: a 3x3x3 g, negative at the centre
g = struct.pack("<27f", *[1.0] * 13 + [-0.5] + [1.0] * 13)
fields = "imgmesh_kind:=pu-implicit\nimgmesh_version:=1\nimgmesh_d:=1.5 1.5 1.5"
put("implicit", "good", nrrd([3, 3, 3], typ="float", payload=g, extra=fields))
put("implicit", "bad-d", nrrd([3, 3, 3], typ="float", payload=g, extra=fields.replace("1.5 1.5 1.5", "0 nan 1e308")))
put("implicit", "zero-sample", nrrd([3, 3, 3], typ="float", payload=struct.pack("<27f", *[0.0] * 27), extra=fields))
put("implicit", "2d", nrrd([3, 3], typ="float", payload=g[:36], extra=fields))

# implicit-eval point lines: selector bit 0 --gradient, bit 1 --allow-outside
put("implicit_eval", "points", b"\0" + b"1 1 1\n0.5 0.25 2 # comment\n\n  2\t1  3  \n")
put("implicit_eval", "outside", b"\3" + b"-5 0 0\n1e308 1e308 1e308\n")
put("implicit_eval", "bad", b"\1" + b"1 2\nnan 0 0\n1 2 3 4\n")

# Triangle: selector 0 .node, 1 .poly(+.node after a NUL), 2 .ele(+.node after a NUL)
node = "4 2 1 1\n1 0 0 5 1\n2 1 0 5 1\n3 1 1 5 1\n4 0 1 5 1\n"
put("triangle", "node", "\0" + node)
put("triangle", "node-comments", "\0# square\n4 2 0 0 # header\n0 0 0\n1 1 0\n2 1 1\n3 0 1\n")
put("triangle", "poly-inline", "\1" + node + "4 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 1 1\n1\n1 0.5 0.5\n1\n1 0.2 0.2 3 0.1\n")
put("triangle", "poly-node", "\1" + "0 2 0 0\n2 0\n1 1 2\n2 2 3\n0\n\0" + node)
put("triangle", "ele", "\2" + "2 3 1\n1 1 2 3 7\n2 1 3 4 7\n\0" + node)
put("triangle", "ele-quad", "\2" + "1 4 0\n1 1 2 3 4\n\0" + node)
put("triangle", "ele-dangling", "\2" + "1 3 0\n1 1 2 9\n\0" + node)
put("triangle", "ele-huge-count", "\2" + "2000000000 3 0\n1 1 2 3\n\0" + "2000000000 2 0 0\n1 0 0\n")

# planar OFF: selector bit 0 = standard input
sq = "OFF\n5 4 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 0\n3 0 1 4\n3 1 2 4\n3 2 3 4\n3 3 0 4\n"
put("planar_off", "tris", "\0" + sq)
put("planar_off", "stdin", "\1" + sq)
put("planar_off", "quad", "\0OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n")
put("planar_off", "huge-count", "\0OFF\n2000000000 2000000000 0\n0 0 0\n")
put("planar_off", "bad-id", "\0OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n")

# tri2quad and quadsmooth: OFF meshes (selector bits: options)
put("tri2quad", "square", "\0" + sq)
put("tri2quad", "square-pairs", "\2" + sq)
strip = "OFF\n8 6 0\n0 0 0\n1 0 0\n2 0 0\n3 0 0\n0 1 0\n1 1 0\n2 1 0\n3 1 0\n" \
        "3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n"
put("tri2quad", "strip", "\1" + strip)
grid = ["OFF", "9 4 0"] + ["%d %d 0" % (x, y) for y in range(3) for x in range(3)]
grid += ["4 0 1 4 3", "4 1 2 5 4", "4 3 4 7 6", "4 4 5 8 7"]
put("quadsmooth", "grid", "\1" + "\n".join(grid) + "\n")
put("quadsmooth", "grid-slide", "\2" + "\n".join(grid).replace("4 4 0", "4.3 3.8 0") + "\n")
put("quadsmooth", "mixed", "\3OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0.5 0\n4 0 1 2 3\n3 1 4 2\n")
put("quadsmooth", "flipped", "\1OFF\n4 1 0\n0 0 0\n0 1 0\n1 1 0\n1 0 0\n4 0 1 2 3\n")

# surfaces: selector 0 .off, 1 .ply, 2 .obj, 3 .stl, 4 OFF on standard input, 5 .vtp, 6 .vtk
tet = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n"
put("surface", "off", "\0" + tet)
put("surface", "off-stdin", "\4" + tet)
put("surface", "off-quad", "\0OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n")
put("surface", "ply-ascii", "\1ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
put("surface", "ply-binary", b"\1ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
    b"property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
    + struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<B3i", 3, 0, 1, 2))
put("surface", "obj", "\2v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n")
put("surface", "stl-ascii", "\3solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
    "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n")
put("surface", "stl-binary", b"\3" + b"\0" * 80 + struct.pack("<I", 1) + struct.pack("<12f", 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0)
    + b"\0\0")
put("surface", "stl-binary-huge-count", b"\3" + b"\0" * 80 + struct.pack("<I", 0xffffffff) + b"\0" * 50)

# tetrahedral meshes: selector 0 .msh, 1 .mesh, 2 .vtu, 3 .vtk; one tetrahedron and its boundary
pts = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
put("volume", "msh22", "\0$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
    "$EndNodes\n$Elements\n2\n1 4 2 1 1 1 2 3 4\n2 2 2 1 1 1 3 2\n$EndElements\n")
put("volume", "msh41", "\0$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"region_1\"\n$EndPhysicalNames\n"
    "$Entities\n0 0 0 1\n1 0 0 0 1 1 1 1 1 0\n$EndEntities\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n" + pts +
    "$EndNodes\n$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n")
put("volume", "medit", "\1MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
    "Triangles\n1\n1 3 2 1\nTetrahedra\n1\n1 2 3 4 1\nEnd\n")
put("volume", "vtu", "\2<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\">\n<UnstructuredGrid>\n"
    "<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" "
    "format=\"ascii\">\n" + pts + "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" "
    "format=\"ascii\">\n0 1 2 3\n</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n4\n</DataArray>\n"
    "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n10\n</DataArray>\n</Cells>\n<CellData>\n"
    "<DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n1\n</DataArray>\n</CellData>\n</Piece>\n"
    "</UnstructuredGrid>\n</VTKFile>\n")

# The same tetrahedron in the binary forms imgmesh writes: Gmsh binary
# (int 1 for the byte order; 2.2 element runs, 4.1 size_t tags) and a .vtu
# with appended raw data, zlib-compressed behind UInt64 headers.
xyz = [0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1]
head = lambda v: b"\0$MeshFormat\n" + v + b" 1 8\n" + struct.pack("<i", 1) + b"\n$EndMeshFormat\n"
put("volume", "msh22-binary", head(b"2.2") + b"$Nodes\n4\n" +
    b"".join(struct.pack("<iddd", i + 1, *xyz[3 * i:3 * i + 3]) for i in range(4)) + b"\n$EndNodes\n$Elements\n2\n" +
    struct.pack("<3i", 4, 1, 2) + struct.pack("<7i", 1, 1, 1, 1, 2, 3, 4) +
    struct.pack("<3i", 2, 1, 2) + struct.pack("<6i", 2, 1, 1, 1, 3, 2) + b"\n$EndElements\n")
put("volume", "msh41-binary", head(b"4.1") + b"$Entities\n" + struct.pack("<4Q", 0, 0, 0, 1) +
    struct.pack("<i6dQiQ", 1, 0, 0, 0, 1, 1, 1, 1, 1, 0) + b"\n$EndEntities\n$Nodes\n" + struct.pack("<4Q", 1, 4, 1, 4) +
    struct.pack("<3iQ", 3, 1, 0, 4) + struct.pack("<4Q", 1, 2, 3, 4) + struct.pack("<12d", *xyz) +
    b"\n$EndNodes\n$Elements\n" + struct.pack("<4Q", 1, 1, 1, 1) + struct.pack("<3iQ", 3, 1, 4, 1) +
    struct.pack("<5Q", 1, 1, 2, 3, 4) + b"\n$EndElements\n")
appended, tags = b"", []
for typ, name, comps, raw in [("Float64", None, 3, struct.pack("<12d", *xyz)), ("Int64", "connectivity", 1, struct.pack("<4q", 0, 1, 2, 3)),
                              ("Int64", "offsets", 1, struct.pack("<q", 4)), ("UInt8", "types", 1, b"\x0a"),
                              ("Int32", "region", 1, struct.pack("<i", 1))]:
    z = zlib.compress(raw)
    tags.append('<DataArray type="%s"%s%s format="appended" offset="%d"/>\n' % (
        typ, ' Name="%s"' % name if name else "", ' NumberOfComponents="3"' if comps == 3 else "", len(appended)))
    appended += struct.pack("<4Q", 1, 32768, len(raw), len(z)) + z
put("volume", "vtu-appended-zlib", ("\2<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
    "byte_order=\"LittleEndian\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">\n<UnstructuredGrid>\n"
    "<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n<Points>\n" + tags[0] + "</Points>\n<Cells>\n" + "".join(tags[1:4]) +
    "</Cells>\n<CellData>\n" + tags[4] + "</CellData>\n</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n   _").encode()
    + appended + b"\n</AppendedData>\n</VTKFile>\n")

# Layouts of VTK's own writers (vtkXMLWriter's default: appended base64
# data, zlib, UInt32 header; the header one base64 run, the blocks the
# next; inline binary always base64; big-endian with UInt64 headers
# uncompressed) and legacy 5.1 / 4.2 grids and polydata.
b64 = lambda b: base64.b64encode(b).decode()
def vtk_zlib32(raw):
    z = zlib.compress(raw)
    return b64(struct.pack("<4I", 1, 32768, len(raw), len(z))) + b64(z)
appended, tags = "", []
for typ, name, raw in [("Int64", "connectivity", struct.pack("<4q", 0, 1, 2, 3)), ("Int64", "offsets", struct.pack("<q", 4)),
                       ("UInt8", "types", b"\x0a"), ("Int32", "region", struct.pack("<i", 1))]:
    tags.append('<DataArray type="%s" Name="%s" format="appended" offset="%d"/>\n' % (typ, name, len(appended)))
    appended += vtk_zlib32(raw)
put("volume", "vtu-base64-zlib", "\2<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
    "byte_order=\"LittleEndian\" header_type=\"UInt32\" compressor=\"vtkZLibDataCompressor\">\n<UnstructuredGrid>\n"
    "<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" "
    "format=\"binary\">\n" + vtk_zlib32(struct.pack("<12d", *xyz)) + "\n</DataArray>\n</Points>\n<Cells>\n" +
    "".join(tags[:3]) + "</Cells>\n<CellData>\n" + tags[3] + "</CellData>\n</Piece>\n</UnstructuredGrid>\n"
    "<AppendedData encoding=\"base64\">\n   _" + appended + "\n</AppendedData>\n</VTKFile>\n")
put("volume", "vtk-grid-5.1", "\3# vtk DataFile Version 5.1\nvtk output\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n" +
    pts + "CELLS 3 7\nOFFSETS vtktypeint64\n0 4 7\nCONNECTIVITY vtktypeint64\n0 1 2 3 0 2 1\nCELL_TYPES 2\n10\n5\n"
    "CELL_DATA 2\nFIELD FieldData 1\nregion 1 2 int\n1 1\n")
put("volume", "vtk-grid-binary-4.2", b"\3# vtk DataFile Version 4.2\nvtk output\nBINARY\nDATASET UNSTRUCTURED_GRID\n"
    b"POINTS 4 double\n" + struct.pack(">12d", *xyz) + b"\nCELLS 1 5\n" + struct.pack(">5i", 4, 0, 1, 2, 3) +
    b"\nCELL_TYPES 1\n" + struct.pack(">i", 10) + b"\nCELL_DATA 1\nSCALARS region int 1\nLOOKUP_TABLE default\n" +
    struct.pack(">i", 1) + b"\n")
put("volume", "inp", "\4*HEADING\nx\n*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n"
    "*ELEMENT, TYPE=C3D4, ELSET=REGION_1\n1, 1, 2, 3, 4\n*ELEMENT, type=CPS3, ELSET=Surface1\n2, 1, 3, 2\n"
    "*ELSET, ELSET=BOUNDARY_1_S1\n1\n*SURFACE, TYPE=ELEMENT, NAME=BOUNDARY_1\nBOUNDARY_1_S1, S1\n"
    "*ELSET,ELSET=PhysicalVolume1, GENERATE\n1, 1, 1\n")
faces = [0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2]
appended, tags = "", []
for typ, name, comps, raw in [("Float64", "Points", 3, struct.pack(">12d", *xyz)), ("Int32", "connectivity", 1, struct.pack(">12i", *faces)),
                              ("Int32", "offsets", 1, struct.pack(">4i", 3, 6, 9, 12)), ("Int32", "labels", 2, struct.pack(">8i", 1, 0, 1, 0, 1, 0, 1, 0))]:
    tags.append('<DataArray type="%s" Name="%s" NumberOfComponents="%d" format="appended" offset="%d"/>\n' % (
        typ, name, comps, len(appended)))
    appended += b64(struct.pack(">Q", len(raw)) + raw)
put("surface", "vtp-base64-big-endian", "\5<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" "
    "byte_order=\"BigEndian\" header_type=\"UInt64\">\n<PolyData>\n<Piece NumberOfPoints=\"4\" NumberOfPolys=\"4\">\n"
    "<CellData>\n" + tags[3] + "</CellData>\n<Points>\n" + tags[0] + "</Points>\n<Polys>\n" + "".join(tags[1:3]) +
    "</Polys>\n</Piece>\n</PolyData>\n<AppendedData encoding=\"base64\">\n   _" + appended + "\n</AppendedData>\n</VTKFile>\n")
put("surface", "vtk-polydata-5.1", "\6# vtk DataFile Version 5.1\nvtk output\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n" + pts +
    "POLYGONS 5 12\nOFFSETS vtktypeint64\n0 3 6 9 12\nCONNECTIVITY vtktypeint64\n" + " ".join(map(str, faces)) +
    "\nCELL_DATA 4\nFIELD FieldData 1\nlabels 2 4 int\n1 0 1 0 1 0 1 0\n")
