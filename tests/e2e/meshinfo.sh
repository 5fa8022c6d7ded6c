#!/usr/bin/env bash
# meshinfo end to end: hand-made closed and open surfaces with several
# components (OFF), a planar quad mesh (.ele), --json keys, --image against a
# hand-written well-composed NRRD, the certificate by correspondence on a
# ball and a torus meshed by the real tools (and that mesh mirrored), its 2D
# form on a disk and an annulus through img2poly, poly2tri, tri2quad and
# quadsmooth (and those meshes mirrored), and bad input.
source "$(dirname "$0")/lib.sh"
M="$BIN/meshinfo"
# First line of a compact JSON value: "components" and "euler" are the first keys.
comps() { "$M" --json "$1" | tr -d ' \n' | sed -n 's/^{"components":\([0-9]*\),"euler":\[\([-0-9,]*\)\].*/\1 \2/p'; }

# A cube (a sphere, euler 2) as OFF quads, outward; two cubes and an open
# box (cube without its top: a disk, euler 1); a torus of 6 x 4 quads.
surfaces() {
cat > cube.off <<'O'
OFF
8 6 0
0 0 0
1 0 0
0 1 0
1 1 0
0 0 1
1 0 1
0 1 1
1 1 1
4 0 2 3 1
4 4 5 7 6
4 0 1 5 4
4 2 6 7 3
4 0 4 6 2
4 1 3 7 5
O
{
  echo OFF; echo "24 17 0"
  for s in 0 3 6; do sed -n '3,10p' cube.off | awk -v s=$s '{ print $1 + s, $2, $3 }'; done
  for s in 0 8; do sed -n '11,16p' cube.off | awk -v s=$s '{ print $1, $2 + s, $3 + s, $4 + s, $5 + s }'; done
  sed -n '11,16p' cube.off | grep -v '^4 4 5 7 6$' | awk '{ print $1, $2 + 16, $3 + 16, $4 + 16, $5 + 16 }'
} > three.off
awk 'BEGIN { n = 6; m = 4; print "OFF"; print n * m, n * m, 0
  for (j = 0; j < m; j++) for (i = 0; i < n; i++) {
    u = 2 * 3.14159265 * i / n; v = 2 * 3.14159265 * j / m
    printf "%.6f %.6f %.6f\n", (3 + cos(v)) * cos(u), (3 + cos(v)) * sin(u), sin(v) }
  for (j = 0; j < m; j++) for (i = 0; i < n; i++)
    print 4, j * n + i, j * n + (i + 1) % n, ((j + 1) % m) * n + (i + 1) % n, ((j + 1) % m) * n + i }' > torus.off
}

case_components_euler_boundary_loops() {
  surfaces
[ "$(comps cube.off)" = "1 2" ] || fail "cube: $(comps cube.off)"
out=$(comps three.off)
[ "$out" = "3 2,2,1" ] || fail "two cubes and an open box: '$out'"
OUT=three.txt expect 0 meshinfo three.off
grep -q "1 boundary loop" three.txt || fail "open box: no boundary loop in the text report"
}

case_torus_genus_1() {
  surfaces
[ "$(comps torus.off)" = "1 0" ] || fail "torus: $(comps torus.off)"
"$M" --json torus.off | grep -q '"genus": 1' || fail "torus genus"
}

case_off_on_stdin_is_the_file() {
  surfaces
[ "$("$M" --json - < cube.off | tr -d ' \n' | grep -c '^{"components":1,"euler":\[2\],')" = 1 ] || fail "stdin"
  expect 0 meshinfo --json cube.off
  mv out.txt file.json
  IN=cube.off expect 0 meshinfo --json -
  cmp -s out.txt file.json || fail "- differs from the file"
}

case_planar_quad_strip() {
printf '6 2 0 0\n0 0 0\n1 1 0\n2 2 0\n3 0 1\n4 1 1\n5 2 1\n' > strip.node
printf '2 4 0\n0 0 1 4 3\n1 1 2 5 4\n' > strip.ele
[ "$(comps strip.ele)" = "1 1" ] || fail "strip: $(comps strip.ele)"
"$M" --json strip.ele | grep -q '"non_convex": 0' || fail "strip quads convex"
"$M" --json strip.ele | sed -n 's/.*"min_mu": *\([0-9.e+-]*\).*/\1/p' | awk '{ exit !($1 > 44.999 && $1 <= 45) }' \
  || fail "strip: squares have mu 45"
}

# --image: one voxel in a 4^3 NRRD (well-composed); the cube matches it,
# three.off does not (exit 3).
case_image_one_voxel_matches_the_cube_only() {
  surfaces
{ printf 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n\n'
  for i in $(seq 0 63); do if [ $i = 21 ]; then printf '\001'; else printf '\000'; fi; done; } > voxel.nrrd
OUT=img.txt expect 0 meshinfo cube.off --image voxel.nrrd
grep -q "MATCHES" img.txt || fail "no match line"
expect 3 meshinfo three.off --image voxel.nrrd --json
mv out.txt three-file.json
IN=three.off expect 3 meshinfo - --image voxel.nrrd --json
sed 's/"three.off"/"-"/' three-file.json | cmp -s - out.txt || fail "exit 3: MESH - differs from the file"
# Two voxels sharing only an edge: not well-composed, refused.
{ printf 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n\n'
  for i in $(seq 0 63); do if [ $i = 21 ] || [ $i = 26 ]; then printf '\001'; else printf '\000'; fi; done; } > edge.nrrd
expect 1 meshinfo cube.off --image edge.nrrd
grep -q "well-composed" err.txt || fail "message does not say well-composed"
}

# The certificate by correspondence through the real tools: a ball around
# x = 10 and a solid torus around x = 29 in a 40 x 24 x 24 grid. The mesh
# passes; mirrored in x about the grid's centre (faces flipped, so the
# sphere sits where the torus is) it has the same sorted Euler list and must
# be refused.
case_certificate_ball_torus_through_pipeline_and_mirror() {
python3 - <<'P'
import math
nx, ny, nz = 40, 24, 24
b = bytearray()
for z in range(nz):
    for y in range(ny):
        for x in range(nx):
            ball = (x - 10) ** 2 + (y - 11.5) ** 2 + (z - 11.5) ** 2 <= 36
            torus = (math.hypot(x - 29, y - 11.5) - 6) ** 2 + (z - 11.5) ** 2 <= 2.5 ** 2
            b.append(1 if ball or torus else 0)
open('two.nrrd', 'wb').write(b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 40 24 24\nencoding: raw\n\n" + bytes(b))
P
expect 0 img2wc two.nrrd two-wc.nrrd && expect 0 wc2implicit two-wc.nrrd two-f.nrrd &&
  expect 0 implicit2mesh two-f.nrrd two.off || return
OUT=two.json expect 0 meshinfo --json two.off --image two-wc.nrrd || fail "the right mesh of a ball and a torus"
[ "$(comps two.off)" = "2 0,2" ] || fail "two.off: $(comps two.off)"
# Two mesh components, two bdCA(X) components, the certificate: 5 verdicts ok.
[ "$(tr -d ' \n' < two.json | grep -o '"verdict":"ok"' | wc -l)" = 5 ] || fail "two.off: not 5 ok verdicts"
python3 - two.off two-wc.nrrd > swapped.off <<'P'
import re, sys
# Mirror an OFF mesh in x about the centre of an axis-aligned NRRD grid; flip faces.
head = open(sys.argv[2], 'rb').read().split(b'\n\n', 1)[0].decode()
n = int(re.search(r'sizes: *(\d+)', head).group(1))
o = float(re.search(r'space origin: *\(([^,]*),', head).group(1))
s = float(re.search(r'space directions: *\(([^,]*),', head).group(1))
c = o + s * (n - 1) / 2
lines = open(sys.argv[1]).read().split('\n')
nv, nf = map(int, lines[1].split()[:2])
out = lines[:2]
out += [' '.join([repr(2 * c - float(l.split()[0]))] + l.split()[1:]) for l in lines[2:2 + nv]]
out += [' '.join([l.split()[0]] + l.split()[1:][::-1]) for l in lines[2 + nv:2 + nv + nf]]
print('\n'.join(out))
P
[ "$(comps swapped.off)" = "2 0,2" ] || fail "swapped.off: $(comps swapped.off)"
OUT=swapped.txt expect 3 meshinfo swapped.off --image two-wc.nrrd || fail "the swapped mesh"
cp err.txt swapped.err
grep -q "DOES NOT MATCH" swapped.txt || fail "swapped: no mismatch line"
# The torus where the ball is has its hole's walls inside the ball, the
# sphere where the torus is lies inside its outer faces: each farther than a
# voxel diagonal from the faces there.
grep -q "mesh #0: unplaced" swapped.txt || fail "swapped: no per-component verdict"
grep -q "first failure: placed" swapped.txt || fail "swapped: no first failure line"
grep -q "not certified against bdCA(X) of two-wc.nrrd: placed: mesh component .: vertex [0-9]* at (.*) is farther than 1.732 (the place tolerance) from" swapped.err ||
  fail "swapped: message $(cat swapped.err)"
# Shifted by 5 voxels: refused at the default tolerance (one voxel
# diagonal), accepted with --place-tolerance 6 (the components are 19 voxels
# apart); the option needs --image and a positive distance.
awk 'NR > 2 && NF == 3 { $1 = sprintf("%.17g", $1 + 5) } { print }' two.off > shifted.off
expect 3 meshinfo shifted.off --image two-wc.nrrd || fail "shifted by 5 voxels"
grep -q ": placed: " err.txt || fail "shifted: $(cat err.txt)"
expect 0 meshinfo shifted.off --image two-wc.nrrd --place-tolerance 6 || fail "shifted, --place-tolerance 6"
expect 2 meshinfo shifted.off --place-tolerance 6
expect 2 meshinfo shifted.off --image two-wc.nrrd --place-tolerance 0
}

# 2D: a disk around x = 16 and an annulus around x = 47 in a 64 x 32 NRRD
# with an origin and a spacing (mirroring x -> 63 - x swaps their places);
# the values V1 (disk) and V2 (annulus) are arguments, for binary and label
# images.
disk_annulus() {  # disk_annulus FILE V1 V2
python3 - "$@" <<'P'
import math, sys
name, v1, v2 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
b = bytearray()
for y in range(32):
    for x in range(64):
        d, a = math.hypot(x - 16, y - 15.5), math.hypot(x - 47, y - 15.5)
        b.append(v1 if d <= 9 else v2 if 4 < a <= 9 else 0)
head = ("NRRD0004\ntype: uchar\ndimension: 2\nspace dimension: 2\nsizes: 64 32\n"
        "space directions: (0.5,0) (0,0.5)\nspace origin: (10,-4)\nencoding: raw\n\n")
open(name, 'wb').write(head.encode() + bytes(b))
P
}
# The README's 2D chain: NAME.1.ele, NAME.q.ele, NAME.qs.ele.
chain_2d() {  # chain_2d NAME IMAGE [img2poly options]
  local n=$1 img=$2; shift 2
  expect 0 img2poly "$img" "$@" $n.poly && expect 0 poly2tri $n.poly $n.1.ele &&
    expect 0 tri2quad $n.1.ele $n.q.ele && expect 0 quadsmooth $n.q.ele $n.qs.ele
}
make_disk_annulus_chain() { disk_annulus da.nrrd 1 1 && chain_2d da da.nrrd; }
# Mirror a Triangle mesh in x about the centre of its bounding box (the
# image's rectangle, for img2poly's meshes): the .node's x, the .ele copied.
mirror_node() {  # mirror_node IN.ele OUT.ele
python3 - "$1" "$2" <<'P'
import shutil, sys
src, dst = sys.argv[1][:-4], sys.argv[2][:-4]
shutil.copy(src + '.ele', dst + '.ele')
rows = [l.split('#')[0].split() for l in open(src + '.node')]
rows = [r for r in rows if r]
xs = [float(r[1]) for r in rows[1:]]
c = (min(xs) + max(xs)) / 2
for r in rows[1:]:
    r[1] = repr(2 * c - float(r[1]))
open(dst + '.node', 'w').write('\n'.join(' '.join(r) for r in rows) + '\n')
P
}
# An OFF (z = 0) of the faces of nonzero region attribute of a .ele.
foreground_off() {  # foreground_off IN.ele OUT.off
python3 - "$1" "$2" <<'P'
import sys
def rows(path):
    return [r for r in (l.split('#')[0].split() for l in open(path)) if r]
node, ele = rows(sys.argv[1][:-4] + '.node'), rows(sys.argv[1])
base, k = int(node[1][0]), int(ele[0][1])
faces = [[int(v) - base for v in r[1:1 + k]] for r in ele[1:] if float(r[1 + k]) != 0]
with open(sys.argv[2], 'w') as o:
    print('OFF', len(node) - 1, len(faces), 0, file=o)
    for r in node[1:]: print(r[1], r[2], 0, file=o)
    for f in faces: print(len(f), *f, file=o)
P
}
# Number of "ok" verdicts in a --json report.
oks() { tr -d ' \n' < "$1" | grep -o '"verdict":"ok"' | wc -l; }

case_planar_chain_every_stage_matches_its_image() {
  local d; d=$(dirname "$(shared da.qs.ele make_disk_annulus_chain)")
  for s in 1 q qs; do
    OUT=$s.json expect 0 meshinfo --json $d/da.$s.ele --image $d/da.nrrd || continue
    # Two mesh regions and two pixel regions (disk euler 1, annulus 0), all ok.
    [ "$(oks $s.json)" = 4 ] || fail "da.$s.ele: not 4 ok verdicts"
    tr -d ' \n' < $s.json | grep -q '"image":{"components":2,"euler":\[1,0\]' || fail "da.$s.ele: image regions"
  done
  OUT=qs.txt expect 0 meshinfo $d/da.qs.ele --image $d/da.nrrd
  grep -q "^regions .*MATCHES" qs.txt || fail "no match line"
}

case_planar_mirrored_mesh_refused() {
  local d; d=$(dirname "$(shared da.qs.ele make_disk_annulus_chain)")
  for s in 1 q qs; do
    mirror_node $d/da.$s.ele m$s.ele
    OUT=m$s.txt expect 3 meshinfo m$s.ele --image $d/da.nrrd || continue
    grep -q "DOES NOT MATCH" m$s.txt || fail "m$s: no mismatch line"
    grep -q "euler differs" m$s.txt || fail "m$s: no per-region verdict"
    grep -q "mesh region . (label 1): euler 1, its pixel region . (label 1) has 0" err.txt ||
      fail "m$s: message $(cat err.txt)"
    [ "$(wc -l < err.txt)" = 1 ] || fail "m$s: the message is not one line"
  done
}

# The bundled lung slice at --threshold 60 (152 critical configurations
# repaired): each stage matches; mirrored, refused.
case_planar_lung_slice_every_stage_and_mirrored() {
  chain_2d r "$DATA/RatLungSlice1.mha" --threshold 60 || return
  for s in 1 q qs; do
    expect 0 meshinfo r.$s.ele --image "$DATA/RatLungSlice1.mha" --threshold 60
    mirror_node r.$s.ele m$s.ele
    expect 3 meshinfo m$s.ele --image "$DATA/RatLungSlice1.mha" --threshold 60
  done
}

# Without region labels (an OFF of the disk's and the annulus's faces only)
# every face is foreground; mirrored, refused.
case_planar_foreground_off_without_labels() {
  local d; d=$(dirname "$(shared da.qs.ele make_disk_annulus_chain)")
  mirror_node $d/da.1.ele m.ele && foreground_off $d/da.1.ele da.off && foreground_off m.ele m.off || return
  OUT=fg.json expect 0 meshinfo --json da.off --image $d/da.nrrd && [ "$(oks fg.json)" = 4 ] ||
    fail "da.off: not 4 ok verdicts"
  expect 3 meshinfo m.off --image $d/da.nrrd
  grep -q "euler 1, its pixel region . (label 1) has 0" err.txt || fail "m.off: message $(cat err.txt)"
}

# A label image (disk 100, annulus 200): img2poly keeps both labels and
# meshinfo matches each region within its label; after img2poly
# --threshold, meshinfo needs the same --threshold (without, the labels
# differ: refused).
case_planar_labels_and_threshold_as_img2poly() {
  disk_annulus la.nrrd 100 200 && chain_2d la la.nrrd && chain_2d th la.nrrd --threshold 150 || return
  OUT=la.json expect 0 meshinfo --json la.qs.ele --image la.nrrd && [ "$(oks la.json)" = 4 ] || fail "la: not 4 ok"
  tr -d ' \n' < la.json | grep -q '"labels":\[100,200\]' || fail "la: pixel region labels"
  OUT=th.json expect 0 meshinfo --json th.qs.ele --image la.nrrd --threshold 150 && [ "$(oks th.json)" = 2 ] ||
    fail "th: the annulus alone is foreground: not 2 ok verdicts"
  expect 3 meshinfo th.qs.ele --image la.nrrd || fail "th without --threshold"
  expect 2 meshinfo th.qs.ele --threshold 150 || fail "--threshold without --image"
}

# Files as VTK's own writers write them (vtk_variants.py: every layout of
# the XML writers, legacy 5.1 and 4.2, ASCII and binary) read to the counts
# VTK holds: seg2mesh's labelled surface certified against its image in
# each (the labels read right), a grid of tetrahedra to its volume by
# region; the surface with one triangle's labels swapped refused, LZ4 and
# LZMA data refused naming the compressor.
case_vtk_written_files_read_in_every_layout() {  # interop
  local py; py=$(python_with vtk)
  [[ -n $py ]] || { echo "skipped: no python with vtk (python3-vtk9)"; return; }
  # $py for every script: it starts faster than a pyenv shim.
  "$py" "$E2E/labels_image.py" labels.nrrd || die "cannot make labels.nrrd"
  expect 0 seg2mesh labels.nrrd fast.vtp --fast -q || return
  "$py" "$E2E/vtk_variants.py" fast.vtp > vtk.txt 2> vtk.err || die "VTK's writers: $(cat vtk.err)"
  [[ $(wc -l < vtk.txt) == 24 ]] || fail "vtk_variants.py wrote $(wc -l < vtk.txt) files, 24 expected"
  local f rest
  while read -r f rest; do
    if [[ $f == *.vtp || $f == surface-* ]]; then
      OUT=$f.json expect 0 meshinfo "$f" --image labels.nrrd --json
    else
      OUT=$f.json expect 0 meshinfo "$f" --json
    fi
  done < vtk.txt
  "$py" - > counts.txt 2>&1 <<'PY' || fail "not what VTK wrote: $(cat counts.txt)"
import json
for line in open('vtk.txt'):
    f, points, cells, *volumes = line.split()
    d = json.load(open(f + '.json'))
    if volumes:
        d = d['tetrahedra']
        got, want = d['volume_by_region'], dict(rv.split(':') for rv in volumes)
        assert got.keys() == want.keys() and all(abs(got[r] - float(v)) <= 1e-9 * float(v) for r, v in want.items()), \
            '%s: volume by region %s, VTK wrote %s' % (f, got, want)
    got = (d['vertices'], d['tetrahedra'] if volumes else d['triangles'])
    assert got == (int(points), int(cells)), '%s: %s points and cells read, VTK wrote %s %s' % (f, got, points, cells)
PY
  OUT=wrong.txt expect 3 meshinfo wrong.vtp --image labels.nrrd || fail "wrong.vtp (one triangle's labels swapped) certified"
  NAMED=lz4.vtp refused meshinfo "compressed by vtkLZ4DataCompressor" lz4.vtp
  NAMED=lzma.vtp refused meshinfo "compressed by vtkLZMADataCompressor" lzma.vtp
}

case_bad_input_exit_1_2() {
  surfaces
head -c 40 cube.off > trunc.off
expect 1 meshinfo trunc.off || fail "truncated OFF"
[ "$(wc -l < err.txt)" = 1 ] || fail "error is not one line"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n' > nan.off
expect 1 meshinfo nan.off || fail "NaN accepted"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n' > id.off
expect 1 meshinfo id.off || fail "bad id accepted"
printf 'OFF\n999999999 999999999 0\n' > huge.off
expect 1 meshinfo huge.off || fail "huge counts accepted"
expect 1 meshinfo nothere.off || fail "missing file"
cp cube.off cube.xyz
expect 1 meshinfo cube.xyz || fail "unknown format"
"$M" 2> /dev/null; [ $? = 2 ] || fail "no argument"
expect 2 meshinfo cube.off --bogus || fail "unknown option"
}

run_cases "$@"
