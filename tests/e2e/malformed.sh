#!/usr/bin/env bash
# Malformed inputs, every tool: empty and truncated files, corrupt
# compression, NaN and infinity, zero and four dimensions, missing data
# files, out-of-range indices, wrong element kinds. Each must be refused
# within seconds with exit 1, one stderr line "TOOL: FILE: ..." saying what
# is wrong, and no output file. The files are made here, small and fixed.
# (Headers that declare too much data: limits.sh.)
source "$(dirname "$0")/lib.sh"

nrrd_header() {  # TYPE SIZES ENCODING [EXTRA LINE]
  printf 'NRRD0004\ntype: %s\ndimension: %s\nsizes: %s\nencoding: %s\n' "$1" "$(wc -w <<<"$2")" "$2" "$3"
  [[ -z "${4:-}" ]] || printf '%s\n' "$4"
  printf '\n'
}

# Images: img2wc, wc2implicit, seg2mesh (3D) and img2poly (2D).
case_images_refused() {
  : >empty.nrrd
  { nrrd_header float "2 2 2" ascii; echo "1 2 nan 4 5 6 7 8"; } >nan.nrrd
  { nrrd_header float "2 2 2" ascii; echo "1 2 inf 4 -5 6 7 8"; } >inf.nrrd
  { nrrd_header uint8 "0 2 2" raw; } >zero.nrrd
  { nrrd_header uint8 "2 2 2 2" raw; printf '0123456789abcdef'; } >four.nrrd
  nrrd_header uint8 "4 4 4" raw "data file: absent.raw" >missing.nhdr
  printf 'ObjectType = Image\nNDims = 3\nDimSize = 4 4 4\nElementType = MET_UCHAR\nElementDataFile = absent.raw\n' >missing.mhd
  head -c 4096 /dev/zero | gzip -9 -c >zeros.gz
  { nrrd_header uint8 "16 16 16" gzip; head -c $(($(stat -c %s zeros.gz) / 2)) zeros.gz; } >truncated-gzip.nrrd
  # Flip bytes inside the deflate stream: a corrupt block or a CRC mismatch.
  { nrrd_header uint8 "16 16 16" gzip; head -c 12 zeros.gz; printf '\377\377\377\377'; tail -c +17 zeros.gz; } >corrupt-gzip.nrrd
  { nrrd_header uint8 "10 10 10" raw; head -c 500 /dev/zero; } >truncated.nrrd
  # dim[0] = 9: niftilib prints its own "** ERROR" line on C's stderr.
  python3 -c 'import struct, sys; h = bytearray(348); struct.pack_into("<i", h, 0, 348); struct.pack_into("<8h", h, 40, 9, 4, 4, 4, 1, 1, 1, 1); struct.pack_into("<h", h, 70, 2); h[344:348] = b"n+1\0"; sys.stdout.buffer.write(bytes(h) + bytes(68))' >baddim.nii
  for tool in img2wc wc2implicit seg2mesh; do
    out=out.nrrd
    [[ $tool == seg2mesh ]] && out=out.ply
    refused $tool "not an image ITK can read" empty.nrrd $out
    refused $tool "NaN values" nan.nrrd $out
    refused $tool "infinite values" inf.nrrd $out
    refused $tool "size is zero" zero.nrrd $out
    refused $tool "4D image: 2D or 3D expected" four.nrrd $out
    refused $tool "absent.raw" missing.nhdr $out
    refused $tool "cannot read the image" missing.mhd $out
    refused $tool "expected 4096 bytes but received" truncated-gzip.nrrd $out
    refused $tool "cannot read the image" corrupt-gzip.nrrd $out
    refused $tool "more than the file" truncated.nrrd $out
    refused $tool "not recognized as a NIFTI file" baddim.nii $out
  done
  { nrrd_header uint8 "4 4 4" raw; head -c 64 /dev/zero; } >volume.nrrd
  refused img2poly "3D image" volume.nrrd out.poly
  { nrrd_header float "2 2" ascii; echo "1 nan 0 1"; } >nan2d.nrrd
  refused img2poly "NaN values" nan2d.nrrd out.poly
  head -c 40 "$DATA/BinaryImage.png" >truncated.png
  refused img2poly "cannot read the image" truncated.png out.poly
}

# MetaImage data that MetaIO reads as zeros, or takes a directory's size
# for: the reader checks the files the header names and inflates its
# compressed data once.
case_metaimage_data_refused() {
  mha() { printf 'ObjectType = Image\nNDims = 3\nDimSize = 4 4 4\nElementType = MET_UCHAR\n%bElementDataFile = %s\n' "$1" "$2"; }
  head -c 16 /dev/zero | tr '\0' '\1' >slice.raw
  { mha "" LIST; printf 'slice.raw\nslice.raw\nslice.raw\n'; } >short-list.mha
  mha "" "slice%d.raw 1 4 1" >pattern-missing.mha
  mha "" "$PWD" >directory.mha
  { mha "CompressedData = True\n" LOCAL; printf 'not deflate data'; } >corrupt.mha
  printf 'ObjectType = Image\nNDims = 99999999999\nDimSize = 4 4 4\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n' >ndims.mha
  python3 -c 'import sys, zlib; sys.stdout.buffer.write(zlib.compress(bytes(60)))' >short.zraw
  mha "CompressedData = True\n" short.zraw >short-inflate.mha
  for tool in img2wc wc2implicit seg2mesh; do
    out=out.nrrd
    [[ $tool == seg2mesh ]] && out=out.ply
    refused $tool "names 3 files, 4 needed" short-list.mha $out
    refused $tool "NDims must be a whole number" ndims.mha $out
    refused $tool "'slice1.raw' is missing" pattern-missing.mha $out
    refused $tool "not a regular file" directory.mha $out
    refused $tool "compressed data is corrupt" corrupt.mha $out
    refused $tool "fewer bytes than its size declares" short-inflate.mha $out
  done
  # The same files made whole are read: the check refuses only what is wrong.
  { mha "" LIST; printf 'slice.raw\nslice.raw\nslice.raw\nslice.raw\n'; } >list.mha
  python3 -c 'import sys, zlib; sys.stdout.buffer.write(zlib.compress(bytes(range(64))))' >whole.zraw
  mha "CompressedData = True\n" whole.zraw >whole.mha
  expect 0 img2wc --threshold 1 -q list.mha list-out.nrrd
  expect 0 img2wc --threshold 1 -q whole.mha whole-out.nrrd
  [[ -s list-out.nrrd && -s whole-out.nrrd ]] || fail "the whole MetaImages gave no output"
}

# The implicit function file: implicit2mesh, implicit2tet and implicit-eval.
case_implicit_files_refused() {
  : >empty.nrrd
  { nrrd_header uint8 "6 6 6" raw; head -c 216 /dev/zero; } >plain.nrrd
  { nrrd_header uint8 "6 6 6" ascii; for z in 0 1 2 3 4 5; do for y in 0 1 2 3 4 5; do for x in 0 1 2 3 4 5; do
    ((x > 0 && x < 5 && y > 0 && y < 5 && z > 0 && z < 5)) && printf '1 ' || printf '0 '; done; done; done; echo; } >cube.nrrd
  expect 0 wc2implicit -q cube.nrrd f.nrrd || die "wc2implicit on a cube failed"
  head -c $(($(stat -c %s f.nrrd) / 2)) f.nrrd >truncated-f.nrrd
  sed 's/^imgmesh_d:=.*/imgmesh_d:=nan nan nan/' f.nrrd >nan-d.nrrd
  sed 's/^imgmesh_version:=.*/imgmesh_version:=99/' f.nrrd >version.nrrd
  for tool in implicit2mesh implicit2tet implicit-eval; do
    out=out.off
    [[ $tool == implicit2tet ]] && out=out.msh
    [[ $tool == implicit-eval ]] && out=
    refused $tool "not a NRRD file" empty.nrrd $out
    refused $tool "not an implicit function file" plain.nrrd $out
    refused $tool "cannot read the image" truncated-f.nrrd $out
    refused $tool "imgmesh_d" nan-d.nrrd $out
    refused $tool "version" version.nrrd $out
  done
}

# Planar meshes: poly2tri (PSLG), tri2quad, quadsmooth, meshinfo.
case_planar_meshes_refused() {
  : >empty.off
  printf '3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n' >tri.node
  printf '1 3 0\n1 1 2 7\n' >tri.ele                        # vertex 7 does not exist
  printf '3 2 0 0\n1 0 0\n2 nan 0\n3 0 1\n' >nan.node
  printf '1 3 0\n1 1 2 3\n' >nan.ele
  cp tri.node short.node
  printf '1 3 0\n1 1 2\n' >short.ele                        # a triangle with two corners
  printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n' >range.off
  printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n' >nan.off
  printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n' >truncated.off
  printf 'OFF\n5 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 1.5 0\n5 0 1 2 4 3\n' >pentagon.off
  printf '4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n2 0\n1 1 9\n2 2 3\n0\n' >range.poly
  printf '4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n' >alone.node
  for tool in poly2tri tri2quad quadsmooth; do
    out=out.off
    [[ $tool == poly2tri ]] && out=out.ele
    refused $tool "not an OFF file" empty.off $out
    refused $tool "vertex 5 does not exist" range.off $out
    refused $tool "line 5: coordinate 'nan' is out of range" nan.off $out
    refused $tool "truncated" truncated.off $out
  done
  refused poly2tri "vertex 9 does not exist" range.poly out.ele
  refused poly2tri "no alone.poly beside it" alone.node out.ele
  refused poly2tri "unknown PSLG format '.ele'" tri.ele out.ele
  for tool in tri2quad quadsmooth meshinfo; do
    out=out.off
    [[ $tool == meshinfo ]] && out=
    refused $tool "vertex 7 does not exist" tri.ele $out
    NAMED=nan.node refused $tool "line 3: coordinate 'nan' is out of range" nan.ele $out
    refused $tool "an element needs 4 fields, has 3" short.ele $out
  done
  printf 'OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n' >quad.off
  refused tri2quad "element 0 is not a triangle" quad.off out.off
  refused tri2quad "faces must have 3 or 4 vertices" pentagon.off out.off
  refused quadsmooth "faces must have 3 or 4 vertices" pentagon.off out.off
}

# Surface meshes: meshinfo.
case_surface_meshes_refused() {
  : >empty.off
  printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n' >range.off
  printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n' >nan.off
  printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n' >truncated.off
  refused meshinfo "not an OFF file" empty.off
  refused meshinfo "bad vertex id '5'" range.off
  refused meshinfo "line 5: coordinate 'nan' is out of range" nan.off
  refused meshinfo "truncated" truncated.off
  printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n' >truncated.ply
  refused meshinfo "cannot read the mesh" truncated.ply
  # OpenMesh loops for ever on a format version it cannot parse (fuzz_surface).
  sed 's/^format ascii 1.0/format ascii f1.0/' truncated.ply >version.ply
  refused meshinfo "bad format line" version.ply
  # A face's vertex count beyond the vertices: OpenMesh reserved it (fuzz_surface).
  { sed -n '1,/^end_header/p' truncated.ply; printf '0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n'; } >count.ply
  refused meshinfo "a face of 300 vertices (3 in the file)" count.ply
  printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n' >range.obj
  refused meshinfo "bad vertex reference .4." range.obj
  printf 'solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n' >truncated.stl
  refused meshinfo "no faces" truncated.stl
  head -c 90 /dev/zero >short-binary.stl
  refused meshinfo "no faces" short-binary.stl
}

# Coordinates out of the range every reader takes (finite, at most 1e30 in
# magnitude, a mesh 0 or at least 1e-30 across: util/coordinates.hpp,
# the man pages), a file a reader: refused naming the line (binary files: the
# vertex) and the value. The first is issue 35's: poly2tri died of SIGFPE.
case_extreme_coordinates_refused() {
  local range="is out of range (finite, at most 1e30 in magnitude)" span="the coordinates span only"
  printf '4 2 0 0\n1 0 0\n2 1e300 0\n3 1e300 1e-300\n4 0 1e300\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n' >huge.poly
  refused poly2tri "line 3: coordinate '1e300' $range" huge.poly out.ele
  printf 'OFF\n3 1 0\n0 0 0\n1e-300 0 0\n0 1e-300 0\n3 0 1 2\n' >tiny.off
  refused poly2tri "$span 1e-300: under 1e-30" tiny.off out.ele
  printf '3 2 0 0\n1 0 0\n2 5e-320 0\n3 0 5e-320\n' >denormal.node
  printf '0 2 0 0\n3 0\n1 1 2\n2 2 3\n3 3 1\n' >denormal.poly
  NAMED=denormal.node refused poly2tri "$span 5e-320" denormal.node out.ele
  printf '3 2 0 0\n1 0 0\n2 1e31 0\n3 0 1\n' >big.node
  printf '1 3 0\n1 1 2 3\n' >big.ele
  NAMED=big.node refused tri2quad "line 3: coordinate '1e31' $range" big.ele out.ele
  printf 'OFF\n4 1 0\n0 0 0\n1 0 0\n1 inf 0\n0 1 0\n4 0 1 2 3\n' >inf.off
  refused quadsmooth "line 5: coordinate 'inf' $range" inf.off out.off
  printf 'OFF\n3 1 0\n0 0 0\n1 0 -1e31\n0 1 0\n3 0 1 2\n' >z.off
  refused meshinfo "line 4: coordinate '-1e31' $range" z.off
  python3 - <<'PY'
import struct, zlib
tet = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
def text(bad):  # the tetrahedron's corners as text, vertex 1's x replaced
    return [[bad if (i, k) == (1, 0) else str(c) for k, c in enumerate(p)] for i, p in enumerate(tet)]
head = ("ply\nformat {}\nelement vertex 4\nproperty {t} x\nproperty {t} y\nproperty {t} z\n"
        "element face 4\nproperty list uchar int vertex_indices\nend_header\n")
open("nan.ply", "w").write(head.format("ascii 1.0", t="float") + "".join(" ".join(p) + "\n" for p in text("nan"))
                           + "".join("3 %d %d %d\n" % f for f in faces))
b = head.format("binary_little_endian 1.0", t="double").encode()
b += b"".join(struct.pack("<3d", *(1e300 if (i, k) == (1, 0) else c for k, c in enumerate(p))) for i, p in enumerate(tet))
open("huge.ply", "wb").write(b + b"".join(struct.pack("<B3i", 3, *f) for f in faces))
open("over.obj", "w").write("".join("v " + " ".join(p) + "\n" for p in text("1e400"))
                            + "".join("f %d %d %d\n" % tuple(v + 1 for v in f) for f in faces))
corner = lambda v, bad: " ".join(text(bad)[v])
open("big.stl", "w").write("solid t\n" + "".join(" facet normal 0 0 0\n  outer loop\n" + "".join(
    "   vertex " + corner(v, "-1e31") + "\n" for v in f) + "  endloop\n endfacet\n" for f in faces) + "endsolid t\n")
b = bytes(80) + struct.pack("<I", 4)
for f in faces:
    b += struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *(float("inf") if (v, k) == (1, 0) else c
                                                                    for k, c in enumerate(tet[v]))) for v in f) + bytes(2)
open("inf.stl", "wb").write(b)
nodes = lambda bad: "".join("%d %s\n" % (i + 1, " ".join(p)) for i, p in enumerate(text(bad)))
els = "".join("%d 2 2 1 1 %d %d %d\n" % (i + 1, *(v + 1 for v in f)) for i, f in enumerate(faces)) + "5 4 2 1 1 1 2 3 4\n"
open("huge.msh", "w").write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n" + nodes("1e300")
                            + "$EndNodes\n$Elements\n5\n" + els + "$EndElements\n")
coords = lambda bad: "".join(" ".join(p) + "\n" for p in text(bad))
open("nan.msh", "w").write("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n" + coords("nan")
                           + "$EndNodes\n$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n")
open("tiny.mesh", "w").write("MeshVersionFormatted 2\nDimension 3\nVertices\n4\n" + "".join(
    " ".join("%g" % (c * 1e-31) for c in p) + " 0\n" for p in tet) + "Tetrahedra\n1\n1 2 3 4 1\nEnd\n")
open("big.vtu", "w").write(
    '<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="0.1">\n<UnstructuredGrid>\n'
    '<Piece NumberOfPoints="4" NumberOfCells="1">\n<Points>\n<DataArray type="Float64" NumberOfComponents="3" format="ascii">\n'
    + coords("1e31") + '</DataArray>\n</Points>\n<Cells>\n<DataArray type="Int64" Name="connectivity" format="ascii">\n0 1 2 3\n'
    '</DataArray>\n<DataArray type="Int64" Name="offsets" format="ascii">\n4\n</DataArray>\n'
    '<DataArray type="UInt8" Name="types" format="ascii">\n10\n</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n')
# The same in the binary forms the tools write (Gmsh's binary .msh 4.1 and
# 2.2, VTK's appended zlib .vtu): the values go through the same check.
bad = lambda v: [[v if (i, k) == (1, 0) else c for k, c in enumerate(p)] for i, p in enumerate(tet)]
Z, I, D = (lambda *v: struct.pack("<%dQ" % len(v), *v)), (lambda *v: struct.pack("<%di" % len(v), *v)), \
    (lambda *v: struct.pack("<%dd" % len(v), *v))
head = b"$MeshFormat\n%s 1 8\n" + I(1) + b"\n$EndMeshFormat\n"
open("nan-binary.msh", "wb").write(
    head % b"4.1" + b"$Nodes\n" + Z(1, 4, 1, 4) + I(3, 1, 0) + Z(4) + Z(1, 2, 3, 4)
    + b"".join(D(*p) for p in bad(float("nan"))) + b"\n$EndNodes\n$Elements\n" + Z(1, 1, 1, 1) + I(3, 1, 4) + Z(1)
    + Z(1, 1, 2, 3, 4) + b"\n$EndElements\n")
open("huge-binary22.msh", "wb").write(
    head % b"2.2" + b"$Nodes\n4\n" + b"".join(I(i + 1) + D(*p) for i, p in enumerate(bad(1e300)))
    + b"\n$EndNodes\n$Elements\n1\n" + I(4, 1, 2) + I(1, 1, 1, 1, 2, 3, 4) + b"\n$EndElements\n")
def vtu(points_type, fmt, bad_value):  # appended zlib arrays as vtkXMLWriter writes them
    data, tags = b"", ""
    for name, typ, f, values in [(None, points_type, fmt, sum(bad(bad_value), [])), ("connectivity", "Int64", "q", [0, 1, 2, 3]),
                                 ("offsets", "Int64", "q", [4]), ("types", "UInt8", "B", [10])]:
        raw = struct.pack("<%d%s" % (len(values), f), *values)
        block = zlib.compress(raw)
        tags += '<DataArray type="%s"%s format="appended" offset="%d"/>\n' % (
            typ, ' Name="%s"' % name if name else ' NumberOfComponents="3"', len(data))
        data += Z(1, 32768, len(raw), len(block)) + block
    points, cells = tags.split("\n", 1)
    return ('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" '
            'header_type="UInt64" compressor="vtkZLibDataCompressor">\n<UnstructuredGrid>\n'
            '<Piece NumberOfPoints="4" NumberOfCells="1">\n<Points>\n' + points + '\n</Points>\n<Cells>\n' + cells
            + '</Cells>\n</Piece>\n</UnstructuredGrid>\n<AppendedData encoding="raw">\n_').encode() + data \
        + b"\n</AppendedData>\n</VTKFile>\n"
open("huge-appended.vtu", "wb").write(vtu("Float64", "d", 1e300))
open("inf-appended.vtu", "wb").write(vtu("Float32", "f", float("-inf")))
open("fine-appended.vtu", "wb").write(vtu("Float64", "d", 1e30))
PY
  refused meshinfo "PLY line 11: coordinate 'nan' $range" nan.ply
  refused meshinfo "node 2: coordinate 'nan' $range" nan-binary.msh
  refused meshinfo "node 2: coordinate '1.0000000000000001e+300' $range" huge-binary22.msh
  refused meshinfo "appended DataArray Points, value 3: coordinate '1.0000000000000001e+300' $range" huge-appended.vtu
  refused meshinfo "appended DataArray Points, value 3: coordinate '-inf' $range" inf-appended.vtu
  # ... while the file is read, 1e30 at the end of the range: the refusals are the check's.
  "$BIN/meshinfo" fine-appended.vtu >/dev/null || fail "meshinfo fine-appended.vtu: exit $?"
  refused meshinfo "PLY vertex 1: coordinate '1.0000000000000001e+300' $range" huge.ply
  refused meshinfo "line 2: coordinate '1e400' $range" over.obj
  refused meshinfo "line 6: coordinate '-1e31' $range" big.stl
  refused meshinfo "STL triangle 0: coordinate 'inf' $range" inf.stl
  refused meshinfo "line 7: coordinate '1e300' $range" huge.msh
  refused meshinfo "line 12: coordinate 'nan' $range" nan.msh
  refused meshinfo "$span 1e-31: under 1e-30" tiny.mesh
  refused meshinfo "line 8: coordinate '1e31' $range" big.vtu
}

run_cases "$@"
