#!/bin/bash
# The surface formats users open (ParaView/Slicer: .vtp, .vtk; Gmsh: .msh
# 4.1 and 2.2; MeshLab/Slicer: PLY with face properties) read back by
# readers that are not ours: VTK's Python readers and meshio where installed
# (skipped with a message where absent), Gmsh itself (it reads each .msh and
# writes it again), and the formats' grammars (surface_read.py). Each output
# must hold the certified OFF's vertices (world coordinates) and triangles
# (winding), a component id per face, and outward unit normals with
# --normals; .msh a physical group per component.
set -euo pipefail
mkdir -p "$TMP"
cd "$TMP"
rm -rf ./*
fail() { echo "FAIL: $*" >&2; exit 1; }
here=$(dirname "$0")
check="$BIN/../tests/unit/surface/surface_check"
# A python that has the module, or none: the pyenv python on PATH may not
# see Debian's python3-vtk9 / python3-meshio.
python_with() {
  for py in python3 /usr/bin/python3; do
    if command -v "$py" > /dev/null && "$py" -c "import $1" 2> /dev/null; then echo "$py"; return; fi
  done
}
VTKPY=$(python_with vtk)
MESHIOPY=$(python_with meshio)

# Two components (a ball and a solid torus) of a rotated anisotropic image.
python3 "$here/labels_image.py" labels.nrrd
"$BIN/img2wc" -q labels.nrrd --label 1 --label 5 wc.nrrd
"$BIN/wc2implicit" -q wc.nrrd f.nrrd
M() { "$BIN/implicit2mesh" -q --threads 1 f.nrrd "$@"; }
M ref.off
"$check" ref.off wc.nrrd 2 || fail "reference OFF not certified"

for out in s.ply s.vtp s.vtk s.msh s22.msh; do
  version=4.1; [ "$out" = s22.msh ] && version=2.2
  M "$out" --normals --msh-version $version
  M "plain-$out" --msh-version $version   # without normals
done
grep -qx "4.1 0 8" s.msh && grep -qx "2.2 0 8" s22.msh || fail "--msh-version not followed"
# One python run for each reader: python's start is most of the time.
PY=${VTKPY:-python3}
$PY "$here/surface_compare.py" ref.off s.ply:text:1e-6 plain-s.ply:text:1e-6 s.msh plain-s.msh s22.msh plain-s22.msh \
  || fail "PLY or msh"
if [ -n "$VTKPY" ]; then
  $VTKPY "$here/surface_compare.py" ref.off s.vtp:vtk plain-s.vtp:vtk s.vtk:vtk plain-s.vtk:vtk || fail "read by VTK"
else
  echo "skipped: no python with vtk (python3-vtk9) to read .vtp and .vtk"
fi
if [ -n "$MESHIOPY" ]; then
  $MESHIOPY "$here/surface_compare.py" ref.off s.msh:meshio s22.msh:meshio || fail "read by meshio"
else
  echo "skipped: no python with meshio to read .msh"
fi
if command -v gmsh > /dev/null; then
  # Gmsh reads each (an error exits non-zero) and writes it again: the
  # physical groups and the triangles are still there.
  for out in s.msh s22.msh; do
    gmsh "$out" -0 -format msh22 -o "gmsh-$out" > gmsh.log 2>&1 || { cat gmsh.log; fail "gmsh cannot read $out"; }
    ! grep -qi "error" gmsh.log || { cat gmsh.log; fail "gmsh: errors reading $out"; }
  done
  $PY - "$here" <<'PY' || fail "gmsh lost triangles or physical groups"
import sys; sys.path.insert(0, sys.argv[1]); import surface_read as r
key = lambda m: sorted((tuple(tuple(round(x, 9) for x in m['points'][v]) for v in t), p)
                       for t, p in zip(m['triangles'], m['physical']))
for f in ('s.msh', 's22.msh'):
    a, b = r.read(f), r.read('gmsh-' + f)
    assert len(b['triangles']) == len(a['triangles']) and key(a) == key(b), f
PY
else
  echo "skipped: no gmsh to read .msh"
fi

# --normals where the format holds none: one warning line, the mesh written.
"$BIN/implicit2mesh" --threads 1 f.nrrd n.off --normals 2> warn.txt
[ -s n.off ] || fail "n.off not written"
[ "$(wc -l < warn.txt)" = 1 ] && grep -q "^implicit2mesh: warning: --normals ignored" warn.txt \
  || { cat warn.txt; fail "--normals with .off: no one-line warning"; }
"$BIN/implicit2mesh" --threads 1 f.nrrd n.ply --normals 2> warn.txt
[ ! -s warn.txt ] || { cat warn.txt; fail "--normals with .ply warned"; }
# Bad choices are usage errors before any work, and leave nothing.
set +e
M x.msh --msh-version 3.0 2> err.txt; rc=$?
set -e
[ $rc = 2 ] && [ ! -e x.msh ] || fail "--msh-version 3.0: exit $rc"
set +e
M x.gts 2> err.txt; rc=$?
set -e
[ $rc = 2 ] && grep -q ".vtp" err.txt || { cat err.txt; fail "unknown extension: exit $rc or the formats not listed"; }
echo "ok"
