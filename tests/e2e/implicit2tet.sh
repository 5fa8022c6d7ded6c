#!/usr/bin/env bash
# implicit2tet end to end: usage errors and bad input leave no file; the
# bundled bunny through the real pipeline into every format, each read back
# by meshinfo (conformity, boundary topology by place against the
# well-composed image) and, where installed, by python3-meshio and gmsh with
# its regions; the volume at a quarter-voxel distance bound against the
# foreground's voxel volume; exit 3 with the mesh written when --max-points
# stops it.
source "$(dirname "$0")/lib.sh"

bunny_wc() { expect 0 img2wc "$DATA/bunny00-96.nrrd" bunny-wc.nrrd -q; }
bunny_f() { local wc; wc=$(shared bunny-wc.nrrd bunny_wc) && expect 0 wc2implicit "$wc" bunny-f.nrrd -q; }
# One mesh a format, made once for the cases that read it.
tet() { local f; f=$(shared bunny-f.nrrd bunny_f) && expect 0 implicit2tet "$f" "$@" -q; }
bunny_msh() { tet bunny.msh --stats stats.json; }
bunny22_msh() { tet bunny22.msh --msh-version 2.2; }
bunny_mesh() { tet bunny.mesh; }
bunny_vtu() { tet bunny.vtu; }
bunny_inp() { tet bunny.inp; }
# mesh NAME: the shared mesh NAME (bunny.msh: bunny_msh) linked into the case's folder.
mesh() { local f; f=$(shared "$1" "$(tr . _ <<< "$1")") && ln -sf "$f" "$1"; }
# small NAME [OPTIONS]: the same for the meshio cases, which read one mesh
# a format: the bunny at a one-voxel distance bound (a fifth of the default's
# CPU time), so each case takes seconds.
small() { local f; f=$(shared "$1" tet "$@" --max-distance 0.0104) && ln -sf "$f" "$1"; }

# refuses STATUS ARGS...: implicit2tet exits STATUS with one stderr line.
refuses() {
  OUT=stdout.txt expect "$@" || return
  [[ $(wc -l < err.txt) == 1 ]] || fail "implicit2tet ${*:2}: not one line on stderr: $(cat err.txt)"
}
no_output_left() {
  local left; left=$(ls | grep -v -e '^err.txt$' -e '^stdout.txt$' -e '^empty.nrrd$')
  [[ -z $left ]] || fail "output written on error: $left"
}

case_usage_errors_exit_2_without_output() {
  local f; f=$(shared bunny-f.nrrd bunny_f) || return
  refuses 2 implicit2tet
  refuses 2 implicit2tet "$f" out.stl
  refuses 2 implicit2tet "$f" -
  refuses 2 implicit2tet "$f" out.msh --cell-ratio 1.5
  refuses 2 implicit2tet "$f" out.msh --cell-size -1
  refuses 2 implicit2tet "$f" out.msh --msh-version 3.0
  refuses 2 implicit2tet "$f" out.msh --ratio 1.1
  no_output_left
}

case_bad_input_exit_1_without_output() {
  local f; f=$(shared bunny-f.nrrd bunny_f) || return
  refuses 1 implicit2tet missing.nrrd out.msh
  refuses 1 implicit2tet "$DATA/bunny00-96.nrrd" out.msh   # not an implicit function file
  : > empty.nrrd
  refuses 1 implicit2tet empty.nrrd out.msh
  refuses 1 implicit2tet "$f" no/such/folder/out.msh
  no_output_left
}

case_default_msh_is_4_1_with_certified_stats() {
  mesh bunny.msh || return
  local stats; stats=$(dirname "$(readlink bunny.msh)")/stats.json
  [[ $(json "$stats" topology_matches) == True ]] || fail "stats: topology_matches"
  [[ $(json "$stats" boundary_is_restricted_surface) == True ]] || fail "stats: the boundary is not the certified surface"
  head -2 bunny.msh | grep -q '^4.1 0 8' || fail "default .msh: not 4.1"
}

case_msh_version_2_2_followed() {
  mesh bunny22.msh || return
  head -2 bunny22.msh | grep -q '^2.2 0 8' || fail "--msh-version 2.2: not a 2.2 file"
}

# meshinfo reads it back: conforming, positive, the boundary matching
# bdCA(X) by place with every voxel centre next to it on its side,
# radius-edge ratios within 2.
read_back() {
  mesh "$1" || return
  OUT=info.json expect 0 meshinfo "$1" --image "$(shared bunny-wc.nrrd bunny_wc)" --json ||
    { fail "$1: meshinfo refuses it or it does not match bdCA(X)"; return; }
  python3 - info.json "$1" > report.txt 2>&1 <<'PY' || fail "$1: meshinfo's report: $(cat report.txt)"
import json, sys
r = json.load(open(sys.argv[1]))
t = r["tetrahedra"]
assert r["image"]["matches"], "boundary does not match bdCA(X)"
assert t["conformity"]["conforming"] and t["conformity"]["nonpositive_tetrahedra"] == 0
assert t["max_radius_edge_ratio"] <= 2 * (1 + 1e-9), t["max_radius_edge_ratio"]
assert t["min_dihedral_degrees"] >= 10, t["min_dihedral_degrees"]  # slivers refined (default --sliver-angle 10)
assert t["tetrahedra"] > 1000 and t["boundary_triangles_in_file"] == r["faces"], (t["tetrahedra"], r["faces"])
assert list(t["volume_by_region"]) == ["1"]
# VoxelSides (issue 38): every voxel centre next to bdCA(X) on its side of region 1's boundary.
assert r["image"]["voxel_sides"]["wrong_side"] == 0, r["image"]["voxel_sides"]
PY
}
case_msh_read_back_conforming_matching_the_image() { read_back bunny.msh; }
case_msh22_read_back_conforming_matching_the_image() { read_back bunny22.msh; }
case_mesh_read_back_conforming_matching_the_image() { read_back bunny.mesh; }
case_vtu_read_back_conforming_matching_the_image() { read_back bunny.vtu; }

case_meshinfo_inverted_tetrahedron_exit_3() {
  printf 'MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\nTetrahedra\n1\n1 3 2 4 1\nEnd\n' > inverted.mesh
  expect 3 meshinfo inverted.mesh
}

# The volume at a quarter-voxel distance bound (voxels of 0.0103977):
# within 3% of the foreground's voxel volume.
case_volume_within_3_percent_at_quarter_voxel_bound() {
  tet bunny-d.mesh --max-distance 0.0026 || return
  OUT=info.json expect 0 meshinfo bunny-d.mesh --image "$(shared bunny-wc.nrrd bunny_wc)" --json || return
  python3 - info.json > report.txt 2>&1 <<'PY' || fail "volume not within 3% of the voxel volume: $(cat report.txt)"
import json, sys
t = json.load(open(sys.argv[1]))["tetrahedra"]
v, fg = t["volume"], t["foreground_voxel_volume"]
assert abs(v - fg) <= 0.03 * fg, (v, fg)
PY
}

# python3-meshio (the system python, where it is installed) reads every format with its regions.
case_meshio_reads_every_format_with_regions() {  # interop
  if ! /usr/bin/python3 -c 'import meshio' 2>/dev/null; then echo "skipped: python3-meshio not installed"; return; fi
  small bunny_s.msh && small bunny_s22.msh --msh-version 2.2 && small bunny_s.mesh && small bunny_s.vtu &&
    small bunny_s.inp || return
  /usr/bin/python3 - > meshio.txt 2>&1 <<'PY' || fail "meshio reads the outputs differently: $(cat meshio.txt)"
import meshio
n = None
for f, key in [("bunny_s.msh", "gmsh:physical"), ("bunny_s22.msh", "gmsh:physical"), ("bunny_s.mesh", "medit:ref"),
               ("bunny_s.vtu", "region"), ("bunny_s.inp", None)]:
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
}

# The binary outputs (.vtu by default, .msh with --msh-binary) hold what
# their ASCII forms hold: meshio reads the same points (doubles), cells and
# regions; meshinfo the same report, matching the image; gmsh reads the
# binary .msh to the ASCII file's elements and physical groups.
case_binary_vtu_and_msh_read_as_their_ascii_form() {
  small bunny_s.msh && small bunny_s22.msh --msh-version 2.2 && small bunny_s.vtu && small bunny_sa.vtu --ascii &&
    small bunny_sb.msh --msh-binary && small bunny_sb22.msh --msh-version 2.2 --msh-binary || return
  head -c 200 bunny_s.vtu | grep -aq 'compressor="vtkZLibDataCompressor"' && head -2 bunny_sb.msh | grep -aqx '4.1 1 8' ||
    { fail "not binary outputs"; return; }
  local f wc; wc=$(shared bunny-wc.nrrd bunny_wc) || return
  for f in bunny_s.msh bunny_s22.msh bunny_s.vtu bunny_sa.vtu bunny_sb.msh bunny_sb22.msh; do
    OUT=$f.json expect 0 meshinfo "$f" --image "$wc" --json || { fail "meshinfo --image $f"; return; }
  done
  python3 - > info.txt 2>&1 <<'PY' || fail "meshinfo reads a binary file otherwise: $(cat info.txt)"
import json
r = lambda f: {k: v for k, v in json.load(open(f + '.json')).items() if k != 'file'}
for b, a in [('bunny_s.vtu', 'bunny_sa.vtu'), ('bunny_sb.msh', 'bunny_s.msh'), ('bunny_sb22.msh', 'bunny_s22.msh')]:
    assert r(b) == r(a), (b, a)
    assert r(b)['image']['matches'] and r(b)['tetrahedra']['tetrahedra'] > 100, b
PY
  if /usr/bin/python3 -c 'import meshio' 2> /dev/null; then
    /usr/bin/python3 - > meshio.txt 2>&1 <<'PY' || fail "meshio reads a binary file otherwise: $(cat meshio.txt)"
import meshio
for b, a in [('bunny_s.vtu', 'bunny_sa.vtu'), ('bunny_sb.msh', 'bunny_s.msh'), ('bunny_sb22.msh', 'bunny_s22.msh')]:
    x, y = meshio.read(b), meshio.read(a)
    assert (x.points == y.points).all(), (b, 'points')
    assert [c.type for c in x.cells] == [c.type for c in y.cells] and all((p.data == q.data).all() for p, q in zip(x.cells, y.cells)), (b, 'cells')
    assert sorted(x.cell_data) == sorted(y.cell_data) and all((p == q).all() for k in x.cell_data for p, q in zip(x.cell_data[k], y.cell_data[k])), (b, 'cell data')
    assert any(c.type == 'tetra' for c in x.cells), b
PY
  fi
  command -v gmsh > /dev/null || return 0
  for f in bunny_s.msh bunny_sb.msh bunny_s22.msh bunny_sb22.msh; do
    gmsh "$f" -0 -o "re-$f" -format msh22 > gmsh.log 2>&1 && ! grep -q '^Error' gmsh.log || { fail "gmsh cannot read $f: $(cat gmsh.log)"; return; }
  done
  cmp -s re-bunny_sb.msh re-bunny_s.msh && cmp -s re-bunny_sb22.msh re-bunny_s22.msh ||
    fail "gmsh reads the binary .msh to other elements than the ASCII one"
}

# gmsh reads .msh (4.1 and 2.2) and .mesh and writes them again with the
# same elements and physical groups (MEDIT references become elementary
# entities there).
case_gmsh_reads_msh_and_mesh_with_the_same_elements() {
  if ! command -v gmsh > /dev/null; then echo "skipped: gmsh not installed"; return; fi
  for f in bunny.msh bunny22.msh bunny.mesh; do mesh $f || return; done
  for f in bunny.msh bunny22.msh bunny.mesh; do
    gmsh "$f" -0 -o "re-$f.msh" -format msh22 > gmsh.log 2>&1 || { fail "gmsh cannot read $f: $(cat gmsh.log)"; continue; }
    ! grep -q '^Error' gmsh.log || { fail "gmsh: errors reading $f: $(cat gmsh.log)"; continue; }
    local tag=3; [[ $f == bunny.mesh ]] && tag=4
    python3 - "re-$f.msh" bunny22.msh "$tag" > cmp.txt 2>&1 <<'PY' || fail "gmsh read $f with other elements or regions: $(cat cmp.txt)"
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
}

# share/examples/Makefile's volume target on a small bundled label.
case_examples_makefile_volume_matches_its_label() {  # scale
  [[ -x $BIN/img2wc && -x $BIN/wc2implicit ]] || die "the Makefile part needs img2wc and wc2implicit"
  make -s -f "$SRC/share/examples/Makefile" SCAN="$DATA/liver-labels.nrrd" LABELS="85" BIN="$BIN/" OUT=ex volume \
    > make.out 2>&1 || { fail "make volume: $(cat make.out)"; return; }
  OUT=/dev/null expect 0 meshinfo ex/label-85.msh --image ex/label-85.wc.nrrd || fail "make volume: the mesh does not match its label"
  [[ $(json ex/label-85.tet.json exit_status) == 0 ]] || fail "make volume: no --stats or a failed guarantee"
}

# --max-points stops the surface mesher: exit 3, the mesh written.
case_max_points_exit_3_with_the_mesh() {
  expect 3 implicit2tet "$(shared bunny-f.nrrd bunny_f)" small.msh --max-points 300
  [[ -s small.msh ]] || fail "exit 3 without the mesh"
  grep -q "guarantee not met" err.txt || fail "exit 3 without saying which guarantee: $(cat err.txt)"
}

# --outside: regions 1 and 2 fill the image box. The quarter-voxel bound on
# the bunny (whose surface runs within a voxel of the box) is the case an
# earlier --outside refined without end; the point budgets make a runaway
# fail (exit 3) rather than hang.
outside() { tet "$@" --outside --max-points 1500000 --max-cell-points 1000000; }
bunny_out_msh() { outside bunny_out.msh --max-distance 0.0026 --stats stats.json; }
bunny_out22_msh() { outside bunny_out22.msh --msh-version 2.2; }

# The image box's volume and face area from the NRRD header (sizes, space
# directions), independently of the tools.
box_of() {
  python3 - "$1" <<'PY'
import sys
head = open(sys.argv[1], "rb").read(4096).split(b"\n\n")[0].decode("latin-1")
kv = dict(l.split(": ", 1) for l in head.splitlines() if ": " in l)
n = [int(x) for x in kv["sizes"].split()]
dirs = [[float(c) for c in v.strip("()").split(",")] for v in kv["space directions"].split()]
h = [sum(c * c for c in d) ** 0.5 for d in dirs]
e = [n[i] * h[i] for i in range(3)]
print(e[0] * e[1] * e[2], 2 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]))
PY
}

case_outside_quarter_voxel_fills_the_box() {
  mesh bunny_out.msh || return
  local stats wc; stats=$(dirname "$(readlink bunny_out.msh)")/stats.json
  wc=$(shared bunny-wc.nrrd bunny_wc) || return
  [[ $(json "$stats" topology_matches) == True ]] || fail "stats: topology_matches"
  [[ $(json "$stats" boundary_is_restricted_surface) == True ]] || fail "stats: region 1's boundary is not the certified surface"
  OUT=info.json expect 0 meshinfo bunny_out.msh --image "$wc" --json || { fail "meshinfo: region 1 does not match bdCA(X)"; return; }
  read -r vol area < <(box_of "$wc")
  python3 - info.json bunny_out.msh "$vol" "$area" > report.txt 2>&1 <<'PY' || fail "--outside: $(cat report.txt)"
import json, sys
r = json.load(open(sys.argv[1]))
t = r["tetrahedra"]
box, area = float(sys.argv[3]), float(sys.argv[4])
assert r["image"]["matches"], "region 1's boundary does not match bdCA(X)"
assert t["conformity"]["conforming"] and t["conformity"]["nonpositive_tetrahedra"] == 0
assert t["max_radius_edge_ratio"] <= 2 * (1 + 1e-9), t["max_radius_edge_ratio"]
assert t["min_dihedral_degrees"] >= 10, t["min_dihedral_degrees"]  # slivers refined in both regions (measured)
assert sorted(t["volume_by_region"]) == ["1", "2"], t["volume_by_region"]
assert abs(t["volume"] - box) <= 1e-6 * box, (t["volume"], box)
assert abs(t["volume_by_region"]["1"] - t["foreground_voxel_volume"]) <= 0.03 * t["foreground_voxel_volume"]
PY
  OUT=info.txt expect 0 meshinfo bunny_out.msh || return
  grep -Eq '^  volume by region: 1: [0-9.e+-]+ 2: [0-9.e+-]+$' info.txt || fail "meshinfo's text report does not give the volume of each region"
}

# Every format with both regions and the box's triangle group, read by meshio and gmsh where installed.
case_outside_meshio_reads_every_format_with_two_regions() {  # interop
  if ! /usr/bin/python3 -c 'import meshio' 2>/dev/null; then echo "skipped: python3-meshio not installed"; return; fi
  local f
  for f in bunny_so.msh bunny_so.mesh bunny_so.vtu bunny_so.inp; do small $f --outside || return; done
  small bunny_so22.msh --outside --msh-version 2.2 || return
  read -r vol area < <(box_of "$(shared bunny-wc.nrrd bunny_wc)")
  /usr/bin/python3 - "$vol" "$area" > meshio.txt 2>&1 <<'PY' || fail "meshio: $(cat meshio.txt)"
import sys
import meshio
import numpy as np
box, area = float(sys.argv[1]), float(sys.argv[2])
def volume(p, t):
    a, b, c, d = (p[t[:, i]] for i in range(4))
    return np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a)) / 6
def tri_area(p, t):
    a, b, c = (p[t[:, i]] for i in range(3))
    return np.linalg.norm(np.cross(b - a, c - a), axis=1) / 2
for f, key in [("bunny_so.msh", "gmsh:physical"), ("bunny_so22.msh", "gmsh:physical"), ("bunny_so.mesh", "medit:ref"),
               ("bunny_so.vtu", "region"), ("bunny_so.inp", None)]:
    m = meshio.read(f)
    tets = [i for i, c in enumerate(m.cells) if c.type == "tetra"]
    tris = [i for i, c in enumerate(m.cells) if c.type == "triangle"]
    assert len(tets) >= 1, f
    v = np.concatenate([volume(m.points, m.cells[i].data) for i in tets])
    assert (v > 0).all(), f + ": a tetrahedron not positively oriented"
    assert abs(v.sum() - box) <= 1e-6 * box, (f, v.sum(), box)
    if key:
        regions = set(np.concatenate([m.cell_data[key][i] for i in tets]).tolist())
        assert regions == {1, 2}, (f, regions)
        box_area = sum(tri_area(m.points, m.cells[i].data)[m.cell_data[key][i] == 2].sum() for i in tris)
        assert abs(box_area - area) <= 1e-6 * area, (f, box_area, area)
    else:  # Abaqus: region R's boundary is a surface on faces of R's elements
        cs = {k: set(np.concatenate([np.asarray(a, dtype=int).ravel() for a in v if a is not None]).tolist())
              for k, v in m.cell_sets.items()}
        assert "REGION_1" in cs and "REGION_2" in cs, (f, list(cs))
        for r in ("1", "2"):
            sides = [k for k in cs if k.upper().startswith("BOUNDARY_" + r + "_S")]
            assert sides, (f, r, list(cs))
            for k in sides:
                assert cs[k] <= cs["REGION_" + r], (f, k, "has elements of another region")
PY
}

case_outside_gmsh_reads_both_regions() {  # interop
  if ! command -v gmsh > /dev/null; then echo "skipped: gmsh not installed"; return; fi
  for f in bunny_out.msh bunny_out22.msh; do mesh $f || return; done
  for f in bunny_out.msh bunny_out22.msh; do
    gmsh "$f" -0 -o "re-$f.msh" -format msh22 > gmsh.log 2>&1 || { fail "gmsh cannot read $f: $(cat gmsh.log)"; continue; }
    ! grep -q '^Error' gmsh.log || { fail "gmsh: errors reading $f: $(cat gmsh.log)"; continue; }
    python3 - "re-$f.msh" > cmp.txt 2>&1 <<'PY' || fail "gmsh read $f without both regions: $(cat cmp.txt)"
import sys
lines = open(sys.argv[1]).read().split("$Elements\n")[1].split("$EndElements")[0].split("\n")[1:-1]
groups = {(w[1], w[3]) for w in (l.split() for l in lines)}
assert {("4", "1"), ("4", "2"), ("2", "1"), ("2", "2")} <= groups, groups
PY
  done
}

case_outside_usage_and_cap() {
  local f; f=$(shared bunny-f.nrrd bunny_f) || return
  refuses 2 implicit2tet "$f" out.msh --outside --max-cell-points 0
  no_output_left
  expect 3 implicit2tet "$f" capped.msh --outside --max-cell-points 50
  [[ -s capped.msh ]] || fail "exit 3 without the mesh"
  grep -q "max-cell-points" err.txt || fail "exit 3 without naming --max-cell-points: $(cat err.txt)"
}

run_cases "$@"
