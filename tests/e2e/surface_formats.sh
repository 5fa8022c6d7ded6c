#!/usr/bin/env bash
# The surface formats users open (ParaView/Slicer: .vtp, .vtk; Gmsh: .msh
# 4.1 and 2.2; MeshLab/Slicer: PLY with face properties) read back by
# readers that are not ours: VTK's Python readers and meshio where installed
# (skipped with a message where absent), Gmsh itself (it reads each .msh and
# writes it again), and the formats' grammars (surface_read.py). Each output
# must hold the certified OFF's vertices (world coordinates) and triangles
# (winding), a component id per face, and outward unit normals with
# --normals; .msh a physical group per component. The binary forms (the
# default .ply, .vtp, .vtk; .msh with --msh-binary) decode to exactly what
# their text forms (--ascii) hold, read by VTK, meshio, Gmsh and meshinfo.
source "$(dirname "$0")/lib.sh"
CHECK=$BIN/../tests/unit/surface/surface_check

# Two components (a ball and a solid torus) of a rotated anisotropic image.
image_f() {
  python3 "$E2E/labels_image.py" labels.nrrd || return
  expect 0 img2wc labels.nrrd --label 1 --label 5 wc.nrrd -q && expect 0 wc2implicit wc.nrrd f.nrrd -q
}
M() { local f; f=$(shared f.nrrd image_f) && expect 0 implicit2mesh "$f" -q --threads 1 "$@"; }
reference() { M ref.off; }
# Every format with and without --normals (plain-*).
outputs() {
  local out version
  for out in s.ply s.vtp s.vtk s.msh s22.msh; do
    version=4.1; [[ $out == s22.msh ]] && version=2.2
    M "$out" --normals --msh-version $version
    M "plain-$out" --msh-version $version
  done
  for out in a-s.ply a-s.vtp a-s.vtk a-s.stl; do M "$out" --normals --ascii; done
  M b-s.msh --normals --msh-binary
  M b-s22.msh --normals --msh-binary --msh-version 2.2
  M s.stl
}
# Links to the shared image, reference and outputs in the case's folder.
inputs_here() {
  local f; f=$(shared s.ply outputs) && shared ref.off reference > /dev/null || return
  ln -sf "$(dirname "$f")"/{wc.nrrd,f.nrrd,ref.off,s.ply,s.vtp,s.vtk,s.msh,s22.msh,plain-s.ply,plain-s.vtp,plain-s.vtk,plain-s.msh,plain-s22.msh} .
  ln -sf "$(dirname "$f")"/{a-s.ply,a-s.vtp,a-s.vtk,a-s.stl,b-s.msh,b-s22.msh,s.stl} .
}

case_reference_off_certified() {
  inputs_here || return
  "$CHECK" ref.off wc.nrrd 2 > c.txt 2>&1 || fail "reference OFF not certified: $(cat c.txt)"
}

case_msh_version_followed() {
  inputs_here || return
  grep -qx "4.1 0 8" s.msh || fail "s.msh: not 4.1"
  grep -qx "2.2 0 8" s22.msh || fail "--msh-version 2.2 not followed"
}

case_ply_and_msh_hold_the_reference_mesh() {
  inputs_here || return
  local py; py=$(python_with vtk); py=${py:-python3}
  $py "$E2E/surface_compare.py" ref.off s.ply:text:1e-6 plain-s.ply:text:1e-6 a-s.ply:text:1e-6 s.msh plain-s.msh s22.msh plain-s22.msh \
    > cmp.txt 2>&1 || fail "PLY or msh: $(cat cmp.txt)"
}

case_vtp_and_vtk_read_by_vtk() {
  local py; py=$(python_with vtk)
  [[ -n $py ]] || { echo "skipped: no python with vtk (python3-vtk9) to read .vtp and .vtk"; return; }
  inputs_here || return
  $py "$E2E/surface_compare.py" ref.off s.vtp:vtk plain-s.vtp:vtk s.vtk:vtk plain-s.vtk:vtk > cmp.txt 2>&1 ||
    fail "read by VTK: $(cat cmp.txt)"
}

case_msh_read_by_meshio() {
  local py; py=$(python_with meshio)
  [[ -n $py ]] || { echo "skipped: no python with meshio to read .msh"; return; }
  inputs_here || return
  $py "$E2E/surface_compare.py" ref.off s.msh:meshio s22.msh:meshio b-s.msh:meshio b-s22.msh:meshio > cmp.txt 2>&1 ||
    fail "read by meshio: $(cat cmp.txt)"
}

# Each binary output and its --ascii form decode to the same mesh: the
# same doubles (floats in PLY and STL), triangles, component ids, normals,
# physical groups, by VTK (.vtp, .vtk; meshio reads no legacy POLYDATA)
# and meshio (.msh, .stl; its binary PLY reader fails on face properties).
case_binary_outputs_decode_to_their_ascii_mesh() {
  local py; py=$(python_with vtk)
  [[ -n $py ]] && "$py" -c 'import meshio' 2> /dev/null || { echo "skipped: no python with vtk and meshio"; return; }
  inputs_here || return
  head -c 300 s.vtp | grep -aq 'compressor="vtkZLibDataCompressor"' && head -3 s.vtk | grep -aqx BINARY &&
    head -2 s.ply | grep -aqx 'format binary_little_endian 1.0' && head -2 b-s.msh | grep -aqx '4.1 1 8' ||
    { fail "the default outputs are not binary"; return; }
  $py - "$E2E" > same.txt 2>&1 <<'PY' || fail "a binary output decodes to another mesh: $(cat same.txt)"
import sys; sys.path.insert(0, sys.argv[1]); import surface_read as r, meshio
for b, a, reader in [('s.vtp', 'a-s.vtp', 'vtk'), ('s.vtk', 'a-s.vtk', 'vtk'), ('s.ply', 'a-s.ply', 'text'), ('b-s.msh', 's.msh', 'meshio'), ('b-s22.msh', 's22.msh', 'meshio')]:
    x, y = r.read(b, reader), r.read(a, reader)
    assert x == y, (b, a, reader, [k for k in x if x[k] != y.get(k)])
    assert len(x['triangles']) > 100 and x['normals'] is not None and (x['component'] or x['physical']), (b, reader)
for b, a in [('s.stl', 'a-s.stl')]:
    x, y = meshio.read(b), meshio.read(a)
    # STL holds float32: the text's 9 digits are the same floats.
    assert (x.points.astype('float32') == y.points.astype('float32')).all() and len(x.cells) == len(y.cells), (b, a)
    assert all((p.data == q.data).all() for p, q in zip(x.cells, y.cells)), (b, a)
print('same')
PY
}

# meshinfo reads the binary and the ASCII PLY and STL to the same certified mesh.
case_meshinfo_certifies_binary_and_ascii_ply_stl() {
  inputs_here || return
  local f
  for f in s.ply a-s.ply s.stl a-s.stl; do
    OUT=$f.json expect 0 meshinfo "$f" --image wc.nrrd --json || { fail "meshinfo --image $f"; continue; }
  done
  python3 - > info.txt 2>&1 <<'PY' || fail "meshinfo reads them differently: $(cat info.txt)"
import json
r = {f: json.load(open(f + '.json')) for f in ('s.ply', 'a-s.ply', 's.stl', 'a-s.stl')}
strip = lambda d: {k: v for k, v in d.items() if k not in ('input', 'mesh', 'file', 'path')}
assert strip(r['s.ply']) == strip(r['a-s.ply']) and strip(r['s.stl']) == strip(r['a-s.stl'])
assert all(x['image']['matches'] for x in r.values())
PY
}

# Gmsh reads each, ASCII and binary (an error exits non-zero), and writes
# it again: the physical groups and the triangles of the ASCII file are
# still there.
case_gmsh_keeps_triangles_and_physical_groups() {
  command -v gmsh > /dev/null || { echo "skipped: no gmsh to read .msh"; return; }
  inputs_here || return
  local out
  for out in s.msh s22.msh b-s.msh b-s22.msh; do
    gmsh "$out" -0 -format msh22 -o "gmsh-$out" > gmsh.log 2>&1 || { fail "gmsh cannot read $out: $(cat gmsh.log)"; return; }
    ! grep -qi "error" gmsh.log || { fail "gmsh: errors reading $out: $(cat gmsh.log)"; return; }
  done
  local py; py=$(python_with vtk); py=${py:-python3}
  $py - "$E2E" > cmp.txt 2>&1 <<'PY' || fail "gmsh lost triangles or physical groups: $(cat cmp.txt)"
import sys; sys.path.insert(0, sys.argv[1]); import surface_read as r
key = lambda m: sorted((tuple(tuple(round(x, 9) for x in m['points'][v]) for v in t), p)
                       for t, p in zip(m['triangles'], m['physical']))
for f in ('s.msh', 's22.msh', 'b-s.msh', 'b-s22.msh'):
    a, b = r.read(f.replace('b-', '')), r.read('gmsh-' + f)
    assert len(b['triangles']) == len(a['triangles']) and key(a) == key(b), f
PY
}

# --normals where the format holds none: one warning line, the mesh written.
case_normals_with_off_one_warning_and_the_mesh() {
  expect 0 implicit2mesh "$(shared f.nrrd image_f)" n.off --normals --threads 1
  [[ -s n.off ]] || fail "n.off not written"
  [[ $(wc -l < err.txt) == 1 ]] && grep -q "^implicit2mesh: warning: --normals ignored" err.txt ||
    fail "--normals with .off: no one-line warning: $(cat err.txt)"
}

case_normals_with_ply_no_warning() {
  expect 0 implicit2mesh "$(shared f.nrrd image_f)" n.ply --normals --threads 1
  [[ ! -s err.txt ]] || fail "--normals with .ply warned: $(cat err.txt)"
}

# Bad choices are usage errors before any work, and leave nothing.
case_bad_msh_version_exit_2_without_output() {
  expect 2 implicit2mesh "$(shared f.nrrd image_f)" x.msh --msh-version 3.0
  [[ ! -e x.msh ]] || fail "--msh-version 3.0: x.msh left"
}

case_unknown_extension_exit_2_lists_the_formats() {
  expect 2 implicit2mesh "$(shared f.nrrd image_f)" x.gts
  grep -q ".vtp" err.txt || fail "unknown extension: the formats not listed: $(cat err.txt)"
}

run_cases "$@"
