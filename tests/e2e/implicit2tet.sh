#!/bin/bash
# implicit2tet end to end: usage errors and bad input leave no file; the
# bundled bunny through the real pipeline into every format, each read back
# by meshinfo (conformity, boundary topology by place against the
# well-composed image) and, where installed, by python3-meshio and gmsh with
# its regions; the volume at a quarter-voxel distance bound against the
# foreground's voxel volume; exit 3 with the mesh written when --max-points
# stops it.
set -euo pipefail
mkdir -p "$TMP"
cd "$TMP"
rm -rf ./*
tool="$BIN/implicit2tet"
fail() { echo "FAIL: $*" >&2; exit 1; }
[ -x "$tool" ] || fail "no $tool"

expect_status() {  # expect_status CODE command...
  local want=$1; shift
  set +e; "$@" 2>err.txt; local got=$?; set -e
  [ "$got" = "$want" ] || { cat err.txt >&2; fail "exit $got, want $want: $*"; }
  if [ "$want" != 0 ] && [ "$want" != 3 ]; then
    [ "$(wc -l < err.txt)" = 1 ] || { cat err.txt >&2; fail "not one line on stderr: $*"; }
    grep -q '^implicit2tet: ' err.txt || fail "message does not start with the tool's name: $*"
  fi
}

"$BIN/img2wc" -q "$DATA/bunny00-96.nrrd" bunny-wc.nrrd
"$BIN/wc2implicit" -q bunny-wc.nrrd bunny-f.nrrd

expect_status 2 "$tool"
expect_status 2 "$tool" bunny-f.nrrd out.stl
expect_status 2 "$tool" bunny-f.nrrd -
expect_status 2 "$tool" bunny-f.nrrd out.msh --cell-ratio 1.5
expect_status 2 "$tool" bunny-f.nrrd out.msh --cell-size -1
expect_status 2 "$tool" bunny-f.nrrd out.msh --msh-version 3.0
expect_status 2 "$tool" bunny-f.nrrd out.msh --ratio 1.1
expect_status 1 "$tool" missing.nrrd out.msh
expect_status 1 "$tool" "$DATA/bunny00-96.nrrd" out.msh   # not an implicit function file
: > empty.nrrd
expect_status 1 "$tool" empty.nrrd out.msh
expect_status 1 "$tool" bunny-f.nrrd no/such/folder/out.msh
ls out.* 2>/dev/null && fail "output written on error"

# Every format; the default .msh with --stats.
"$tool" -q bunny-f.nrrd bunny.msh --stats stats.json
grep -q '"topology_matches": true' stats.json || fail "stats: topology_matches"
grep -q '"boundary_is_restricted_surface": true' stats.json || fail "stats: the boundary is not the certified surface"
"$tool" -q bunny-f.nrrd bunny22.msh --msh-version 2.2
head -2 bunny22.msh | grep -q '^2.2 0 8' || fail "--msh-version 2.2: not a 2.2 file"
head -2 bunny.msh | grep -q '^4.1 0 8' || fail "default .msh: not 4.1"
for e in mesh vtu inp; do "$tool" -q bunny-f.nrrd "bunny.$e"; done

# meshinfo reads them back: conforming, positive, the boundary matching
# bdCA(X) by place, radius-edge ratios within 2.
for f in bunny.msh bunny22.msh bunny.mesh bunny.vtu; do
  "$BIN/meshinfo" "$f" --image bunny-wc.nrrd --json > info.json || fail "$f: meshinfo refuses it or it does not match bdCA(X)"
  python3 - info.json "$f" <<'PY' || fail "$f: meshinfo's report"
import json, sys
r = json.load(open(sys.argv[1]))
t = r["tetrahedra"]
assert r["image"]["matches"], "boundary does not match bdCA(X)"
assert t["conformity"]["conforming"] and t["conformity"]["nonpositive_tetrahedra"] == 0
assert t["max_radius_edge_ratio"] <= 2 * (1 + 1e-9), t["max_radius_edge_ratio"]
assert t["min_dihedral_degrees"] >= 10, t["min_dihedral_degrees"]  # slivers refined (default --sliver-angle 10)
assert t["tetrahedra"] > 1000 and t["boundary_triangles_in_file"] == r["faces"], (t["tetrahedra"], r["faces"])
assert list(t["volume_by_region"]) == ["1"]
PY
done

# meshinfo refuses a mesh whose tetrahedron is inverted (exit 3).
printf 'MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\nTetrahedra\n1\n1 3 2 4 1\nEnd\n' > inverted.mesh
set +e; "$BIN/meshinfo" inverted.mesh > /dev/null 2> err.txt; got=$?; set -e
[ "$got" = 3 ] || fail "meshinfo: an inverted tetrahedron gives exit $got, not 3"

# The volume at a quarter-voxel distance bound (voxels of 0.0103977):
# within 3% of the foreground's voxel volume.
"$tool" -q bunny-f.nrrd bunny-d.mesh --max-distance 0.0026
"$BIN/meshinfo" bunny-d.mesh --image bunny-wc.nrrd --json > info.json
python3 - info.json <<'PY' || fail "volume not within 3% of the voxel volume"
import json, sys
t = json.load(open(sys.argv[1]))["tetrahedra"]
v, fg = t["volume"], t["foreground_voxel_volume"]
assert abs(v - fg) <= 0.03 * fg, (v, fg)
PY

# python3-meshio (the system python, where it is installed) reads every format with its regions.
if /usr/bin/python3 -c 'import meshio' 2>/dev/null; then
  /usr/bin/python3 - <<'PY' || fail "meshio reads the outputs differently"
import meshio
n = None
for f, key in [("bunny.msh", "gmsh:physical"), ("bunny22.msh", "gmsh:physical"), ("bunny.mesh", "medit:ref"),
               ("bunny.vtu", "region"), ("bunny.inp", None)]:
    m = meshio.read(f)
    tets = [i for i, c in enumerate(m.cells) if c.type == "tetra"]
    assert len(tets) == 1, f
    count = len(m.cells[tets[0]].data)
    n = n or count
    assert count == n, (f, count, n)
    if key:
        regions = set(m.cell_data[key][tets[0]].tolist())
        assert regions == {1}, (f, regions)
        assert any(c.type == "triangle" for c in m.cells), f + ": no boundary triangles"
    else:
        assert "REGION_1" in m.cell_sets, (f, list(m.cell_sets))
PY
else
  echo "skipped: python3-meshio not installed"
fi

# gmsh reads .msh (4.1 and 2.2) and .mesh and writes them again with the
# same elements and physical groups (MEDIT references become elementary
# entities there).
if command -v gmsh > /dev/null; then
  for f in bunny.msh bunny22.msh bunny.mesh; do
    gmsh "$f" -0 -o "re-$f.msh" -format msh22 > gmsh.log 2>&1 || { cat gmsh.log >&2; fail "gmsh cannot read $f"; }
    ! grep -q '^Error' gmsh.log || { cat gmsh.log >&2; fail "gmsh: errors reading $f"; }
    tag=3; [ "$f" = bunny.mesh ] && tag=4
    python3 - "re-$f.msh" bunny22.msh "$tag" <<'PY' || fail "gmsh read $f with other elements or regions"
import sys
tag = int(sys.argv[3])
def elements(path):
    lines = open(path).read().split("$Elements\n")[1].split("$EndElements")[0].split("\n")[1:-1]
    count = {}
    for l in lines:
        w = l.split()
        key = (w[1], w[tag])  # type, physical (3) or elementary (4) tag
        count[key] = count.get(key, 0) + 1
    return count
a, b = elements(sys.argv[1]), elements(sys.argv[2])
assert a == b, (a, b)
PY
  done
else
  echo "skipped: gmsh not installed"
fi

# share/examples/Makefile's volume target on a small bundled label.
[ -x "$BIN/img2wc" ] && [ -x "$BIN/wc2implicit" ] || fail "the Makefile part needs img2wc and wc2implicit"
make -s -f "$SRC/share/examples/Makefile" SCAN="$DATA/liver-labels.nrrd" LABELS="85" BIN="$BIN/" OUT=ex volume
"$BIN/meshinfo" ex/label-85.msh --image ex/label-85.wc.nrrd > /dev/null || fail "make volume: the mesh does not match its label"
grep -q '"exit_status": 0' ex/label-85.tet.json || fail "make volume: no --stats or a failed guarantee"

# --max-points stops the surface mesher: exit 3, the mesh written.
expect_status 3 "$tool" bunny-f.nrrd small.msh --max-points 300
[ -s small.msh ] || fail "exit 3 without the mesh"
grep -q "guarantee not met" err.txt || fail "exit 3 without saying which guarantee"
echo ok
