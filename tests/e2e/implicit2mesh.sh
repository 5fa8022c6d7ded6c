#!/usr/bin/env bash
# implicit2mesh end to end: the real pipeline on bundled images, each mesh
# checked independently (surface_check: closed oriented 2-manifold without
# self-intersections, bdCA(X)'s Euler characteristics, radius-edge ratio;
# surface_check.py: roughness, signed volume, component boxes;
# distance_check.py: the distance bound, through implicit-eval), exit codes,
# stdout against the file output, normals read back, and
# share/examples/Makefile on a bundled multi-label image.
source "$(dirname "$0")/lib.sh"
CHECK=$BIN/../tests/unit/surface/surface_check
SURF=$E2E/surface_check.py

# surface MESH WC RATIO [ROUGHNESS]: both independent surface checkers.
surface() {
  "$CHECK" "$1" "$2" "$3" > check.txt 2>&1 || { fail "$1: surface_check: $(cat check.txt)"; return; }
  python3 "$SURF" "$1" "$2" --roughness "${4:-1.0471975511965976}" > surf.txt 2>&1 || fail "$1: surface_check.py: $(cat surf.txt)"
}
DIST=$E2E/distance_check.py
# spacing F K: K times the smallest voxel spacing of the implicit file F.
spacing() {
  python3 - "$1" "$2" <<'PY'
import re, sys
head = open(sys.argv[1], 'rb').read().split(b'\n\n')[0].decode()
dirs = re.search(r'space directions: (.*)', head).group(1)
print(repr(float(sys.argv[2]) * min(sum(float(x) ** 2 for x in v.strip('()').split(',')) ** 0.5 for v in dirs.split())))
PY
}
bunny_wc() { expect 0 img2wc "$DATA/bunny00-96.nrrd" bunny-wc.nrrd -q; }
bunny_f() { expect 0 wc2implicit "$(shared bunny-wc.nrrd bunny_wc)" bunny-f.nrrd -q; }

case_usage_and_bad_input_exit_1_2_without_output() {
  expect 2 implicit2mesh
  expect 2 implicit2mesh in.nrrd out.xyz
  expect 2 implicit2mesh in.nrrd out.off --ratio 1.1
  expect 2 implicit2mesh in.nrrd out.off --roughness 0.2
  expect 2 implicit2mesh in.nrrd out.off --max-distance -1
  expect 1 implicit2mesh missing.nrrd out.off
  expect 1 implicit2mesh "$DATA/bunny00-96.nrrd" out.off
  # The reason itself (every message starts with "implicit2mesh:").
  grep -q "not an implicit function file" err.txt || fail "a non-implicit file is not named as such: $(cat err.txt)"
  : > empty.nrrd
  expect 1 implicit2mesh empty.nrrd out.off
  [[ $(wc -l < err.txt) == 1 ]] || fail "the error is not one line"
  [[ -z $(ls | grep -v -e '^err.txt$' -e '^out.txt$' -e '^empty.nrrd$') ]] || fail "left: $(ls)"
}

case_bunny_through_pipes_has_voxel_topology() {
  "$BIN/img2wc" -q "$DATA/bunny00-96.nrrd" - | "$BIN/wc2implicit" -q - - > f.nrrd || fail "img2wc | wc2implicit"
  IN=f.nrrd expect 0 implicit2mesh - bunny.ply --stats stats.json
  surface bunny.ply "$(shared bunny-wc.nrrd bunny_wc)" 1.2 2.0943951023931953
  [[ $(json stats.json restricted_delaunay_violations) == 0 ]] || fail "stats: restricted Delaunay violations"
}

case_stdout_is_the_file_output() {
  local f; f=$(shared bunny-f.nrrd bunny_f)
  OUT=stdout.off expect 0 implicit2mesh "$f" - --threads 1
  expect 0 implicit2mesh "$f" file.off --threads 1
  cmp -s stdout.off file.off || fail "OUT - differs from OUT file.off"
  IN=$f OUT=stdin.off expect 0 implicit2mesh - - --threads 1
  cmp -s stdin.off file.off || fail "IN - differs from IN FILE"
}

# At the defaults: ratio 1.2, roughness 120 degrees, every triangle's surface
# centre within 0.4 of the smallest voxel spacing of its plane (0.3 with
# --no-voxel-sides).
case_bunny_defaults_hold_each_bound() {
  local f; f=$(shared bunny-f.nrrd bunny_f)
  expect 0 implicit2mesh "$f" bunny.ply --stats stats.json
  surface bunny.ply "$(shared bunny-wc.nrrd bunny_wc)" 1.2 2.0943951023931953
  python3 - stats.json "$f" surf.txt <<'PY' || fail "bunny at the defaults: a bound exceeded"
import json, math, re, sys
s = json.load(open(sys.argv[1]))
# The roughness the mesher measured is the one read back from the file.
read = math.degrees(float(re.search(r'roughness ([0-9.]+)', open(sys.argv[3]).read()).group(1)))
assert abs(s['max_roughness_degrees'] - read) < 0.01, (s['max_roughness_degrees'], read)
head = open(sys.argv[2], 'rb').read().split(b'\n\n')[0].decode()
dirs = re.search(r'space directions: (.*)', head).group(1)
h = min(sum(float(x) ** 2 for x in v.strip('()').split(',')) ** 0.5 for v in dirs.split())
assert s['max_distance_to_plane'] <= 0.4 * h * (1 + 1e-9), (s['max_distance_to_plane'], h)
assert s['max_roughness_degrees'] <= 120 + 1e-9 and abs(s['roughness_bound_degrees'] - 120) < 1e-9, s['max_roughness_degrees']
assert s['min_angle_degrees'] >= 24.6, s['min_angle_degrees']
PY
  # The distance bound measured, not read from --stats: E = 0.4 of the
  # smallest spacing (the README's default).
  python3 "$DIST" bunny.ply "$f" "$(spacing "$f" 0.4)" "$BIN/implicit-eval" --centroids > dist.txt 2>&1 ||
    fail "bunny at the defaults: $(cat dist.txt)"
}

# VoxelSides (issue 38, on by default): every voxel centre next to bdCA(X)
# on its own side, counted by meshinfo --image's exact side tests and by the
# mesher's own certificate (the bunny had 611 on the wrong side without it).
case_bunny_every_voxel_centre_on_its_side() {
  local f wc; f=$(shared bunny-f.nrrd bunny_f); wc=$(shared bunny-wc.nrrd bunny_wc)
  expect 0 implicit2mesh "$f" sides.off --stats stats.json
  OUT=info.json expect 0 meshinfo sides.off --image "$wc" --json
  [[ $(json info.json image.voxel_sides.wrong_side) == 0 ]] || fail "meshinfo: $(json info.json image.voxel_sides)"
  [[ $(json info.json image.voxel_sides.voxel_centres_checked) -gt 30000 ]] || fail "meshinfo: too few centres checked"
  [[ $(json stats.json voxel_sides.wrong_side) == 0 ]] || fail "stats: $(json stats.json voxel_sides)"
  [[ $(json stats.json points_inserted.voxel_side) -gt 0 ]] || fail "stats: VoxelSides inserted nothing"
}

# The distance bound's centroid half on brain tissue at the defaults: with
# the surface centres alone within E = 0.3 voxel of their planes, a
# triangle of brain label 1 had |f| = 0.63 voxel at its centroid (E is 0.4
# voxel at the defaults now, with VoxelSides).
case_brain_label1_centroids_within_twice_the_bound() {  # scale
  expect 0 img2wc "$DATA/brain-kmeans-labels.nii.gz" --label 1 b1-wc.nrrd -q
  expect 0 wc2implicit b1-wc.nrrd b1-f.nrrd -q
  expect 0 implicit2mesh b1-f.nrrd b1.off
  python3 "$DIST" b1.off b1-f.nrrd "$(spacing b1-f.nrrd 0.4)" "$BIN/implicit-eval" --centroids > dist.txt 2>&1 ||
    fail "brain label 1 at the defaults: $(cat dist.txt)"
}

# The thesis's bounds (rho_0 = 2, 60 degrees, no distance bound) give a
# coarser mesh; radians and degrees are one angle (pi/3 = 60 =
# 1.0471975511965976rad); an old radian value without unit is refused.
LOOSE=(--ratio 2 --max-distance 0)
# Both without VoxelSides: with it, the step alone keeps the mesh near the
# voxel centres, and the thesis's bounds then give more triangles than the
# defaults (the bunny: 13,484 against 12,104).
case_loosened_bounds_and_angle_units() {
  local f; f=$(shared bunny-f.nrrd bunny_f)
  expect 0 implicit2mesh "$f" loose.off "${LOOSE[@]}" --roughness pi/3 --no-voxel-sides --stats loose.json
  surface loose.off "$(shared bunny-wc.nrrd bunny_wc)" 2
  expect 0 implicit2mesh "$f" tight.off --no-voxel-sides --stats tight.json
  python3 - loose.json tight.json <<'PY' || fail "loosened bounds: still acting, or not fewer triangles"
import json, sys
s, d = (json.load(open(a)) for a in sys.argv[1:3])
assert s['max_distance_to_plane'] > d['max_distance_to_plane'], s['max_distance_to_plane']  # --max-distance 0: off
assert s['triangles'] < d['triangles'] and abs(s['roughness_bound_degrees'] - 60) < 1e-9, (s['triangles'], d['triangles'])
PY
  # Without the distance bound the measure finds triangles beyond a quarter
  # voxel (so distance_check.py can fail).
  python3 "$DIST" loose.off "$f" "$(spacing "$f" 0.25)" "$BIN/implicit-eval" > dist.txt 2>&1 &&
    fail "--max-distance 0: every triangle within a quarter voxel: $(cat dist.txt)"
  expect 0 implicit2mesh "$f" loose-deg.off "${LOOSE[@]}" --roughness 60 --no-voxel-sides
  expect 0 implicit2mesh "$f" loose-rad.off "${LOOSE[@]}" --roughness 1.0471975511965976rad --no-voxel-sides
  cmp -s loose.off loose-deg.off && cmp -s loose.off loose-rad.off || fail "--roughness pi/3, 60 and 1.047...rad differ"
  expect 2 implicit2mesh "$f" out.off --roughness 1.5708     # degrees: below the limit
  grep -q "degrees" err.txt || fail "--roughness 1.5708: the message does not name the unit"
  expect 2 implicit2mesh "$f" out.off --roughness pi/x
}

# The normals read back: every one unit and on the outer side of the
# triangles around its vertex (which surface_check finds outward).
case_normals_unit_and_outward() {
  expect 0 implicit2mesh "$(shared bunny-f.nrrd bunny_f)" bunny-n.ply --normals --ratio 2 --max-distance 0.02
  surface bunny-n.ply "$(shared bunny-wc.nrrd bunny_wc)" 2 2.0943951023931953
  python3 "$SURF" bunny-n.ply --normals > n.txt 2>&1 || fail "bunny-n.ply: $(cat n.txt)"
}

# FacetCycle and HandleDetection run on --threads threads, which take
# chunks of the work as they finish: the same mesh for 1, 2 and 3 threads,
# the same bytes of the binary .vtp (exact doubles, zlib-compressed), at
# most 40 bytes a triangle (issue 37).
case_threads_do_not_change_the_mesh() {
  local f; f=$(shared bunny-f.nrrd bunny_f)
  expect 0 implicit2mesh "$f" t1.vtp --threads 1 --stats t1.json
  expect 0 implicit2mesh "$f" t2.vtp --threads 2
  expect 0 implicit2mesh "$f" t3.vtp --threads 3
  cmp -s t1.vtp t2.vtp && cmp -s t1.vtp t3.vtp || fail "--threads 1, 2 and 3 give different meshes"
  local n b; n=$(json t1.json triangles) b=$(stat -c %s t1.vtp)
  (( n > 1000 && b <= 40 * n )) || fail "t1.vtp: $b bytes for $n triangles, over 40 a triangle"
}

# Real brain tissue: a noisy k-means class (289 components, one of genus
# 1482; among them thin rods whose cross-sections nearly fill a Voronoi facet).
case_brain_label5_has_voxel_topology() {  # scale
  expect 0 img2wc "$DATA/brain-kmeans-labels.nii.gz" --label 5 brain-wc.nrrd -q
  expect 0 wc2implicit brain-wc.nrrd brain-f.nrrd -q
  expect 0 implicit2mesh brain-f.nrrd brain.off "${LOOSE[@]}" --stats brain.json
  surface brain.off brain-wc.nrrd 2 2.0943951023931953
  [[ $(json brain.json restricted_delaunay_violations) == 0 ]] || fail "brain: restricted Delaunay violations"
}

# A real organ: CGAL's liver CT labels, the whole organ (35 components, the
# liver's surface of Euler characteristic -6 around its vessels), with
# anisotropic voxels (0.62 x 0.62 x 1.33 mm), at the thesis's bounds.
case_liver_has_voxel_topology() {  # scale
  expect 0 img2wc "$DATA/liver-labels.nrrd" --threshold 1 liver-wc.nrrd -q
  expect 0 wc2implicit liver-wc.nrrd liver-f.nrrd -q
  expect 0 implicit2mesh liver-f.nrrd liver.ply "${LOOSE[@]}" --roughness 60 --threads 2
  surface liver.ply liver-wc.nrrd 2
}

# --max-points: the mesh is written, exit 3, the failed guarantee named;
# - gives the same bytes.
case_max_points_exit_3_with_mesh() {
  local f; f=$(shared bunny-f.nrrd bunny_f)
  expect 3 implicit2mesh "$f" small.off --max-points 40 --threads 1
  grep -q "max-points" err.txt || fail "max-points not named: $(cat err.txt)"
  [[ $(sed -n 2p small.off | cut -d' ' -f2) -gt 0 ]] || fail "max-points: no triangle written"
  OUT=small-stdout.off expect 3 implicit2mesh "$f" - --max-points 40 --threads 1
  cmp -s small.off small-stdout.off || fail "exit 3: OUT - differs from the file output"
}

# The certificate's repairs (tests switch TOPOLOGY off) on a ball and a
# torus: the fallback restores the topology, counted; with no repair round
# the mesh is written, status 3, the failing component named.
case_fallback_repairs_and_exit_3_naming_the_component() {
  python3 - <<'P'
import math
b = bytearray()
for z in range(24):
    for y in range(24):
        for x in range(40):
            ball = (x - 10) ** 2 + (y - 11.5) ** 2 + (z - 11.5) ** 2 <= 36
            torus = (math.hypot(x - 29, y - 11.5) - 6) ** 2 + (z - 11.5) ** 2 <= 2.5 ** 2
            b.append(1 if ball or torus else 0)
open('two.nrrd', 'wb').write(b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 40 24 24\nencoding: raw\n\n" + bytes(b))
P
  expect 0 img2wc two.nrrd two-wc.nrrd -q
  expect 0 wc2implicit two-wc.nrrd two-f.nrrd -q
  expect 0 implicit2mesh two-f.nrrd nt.off "${LOOSE[@]}" --roughness 60 --skip-topology-steps --stats nt.json
  surface nt.off two-wc.nrrd 2
  [[ $(json nt.json topology_fallback_rounds) -ge 1 ]] || fail "fallback: no round counted"
  [[ $(json nt.json topology_fallback_points) -ge 1 ]] || fail "fallback: no point counted"
  expect 3 implicit2mesh two-f.nrrd nt0.off "${LOOSE[@]}" --roughness 60 --skip-topology-steps --fallback-rounds 0
  grep -q "the certificate against the voxel boundary bdCA(X) fails (closed: [0-9]* edge(s) in one triangle only, on mesh component [0-9]*)" err.txt ||
    fail "fallback-rounds 0: $(cat err.txt)"
  [[ -s nt0.off ]] || fail "fallback-rounds 0: no mesh written"
}

# Voxels up to 5:1 (issue 35): a ball and a solid torus (grids of N^3, off
# centre) at spacing 1/5/1 and 1/2.5/0.5, each meshed at the defaults
# within 60 s (under a second here; before the fix each exited 3 on a
# restricted Delaunay violation or refused TOPOLOGY insertions) and
# checked independently. anisotropic SHAPE N CX CY CZ R r SX SY SZ.
anisotropic() {
  python3 - "$@" <<'PY'
import math, sys
shape = sys.argv[1]
n = int(sys.argv[2])
cx, cy, cz, R, r, sx, sy, sz = map(float, sys.argv[3:])
def inside(x, y, z):
    if shape == 'ball':
        return (x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2 <= R * R
    return (math.hypot(x - cx, y - cy) - R) ** 2 + (z - cz) ** 2 <= r * r
b = bytes(1 if inside(x, y, z) else 0 for z in range(n) for y in range(n) for x in range(n))
open('in.nrrd', 'wb').write(("NRRD0004\ntype: uchar\ndimension: 3\nsizes: %d %d %d\nspacings: %r %r %r\nencoding: raw\n\n"
                             % (n, n, n, sx, sy, sz)).encode() + b)
PY
  expect 0 img2wc in.nrrd wc.nrrd -q
  expect 0 wc2implicit wc.nrrd f.nrrd -q
  local start=$SECONDS
  expect 0 timeout 60 "$BIN/implicit2mesh" f.nrrd out.ply --stats stats.json
  ((SECONDS - start <= 60)) || fail "took $((SECONDS - start)) s"
  surface out.ply wc.nrrd 1.2 2.0943951023931953
  [[ $(json stats.json restricted_delaunay_violations) == 0 ]] || fail "restricted Delaunay violations"
  [[ $(json stats.json handle_detection_undecided) == 0 ]] || fail "undecided HandleDetection checks"
}
case_anisotropic_ball_1_5_1() { anisotropic ball 16 7.64 8.02 8.26 6.1 0 1 5 1; }
case_anisotropic_ball_1_2p5_0p5() { anisotropic ball 16 8.15 7.95 7.75 5.5 0 1 2.5 0.5; }
case_anisotropic_torus_1_5_1() { anisotropic torus 18 8.9 8.8 8.8 5.6 1.4 1 5 1; }
case_anisotropic_torus_1_2p5_0p5() { anisotropic torus 16 7.63 7.59 7.77 3.75 1.4 1 2.5 0.5; }

# share/examples/Makefile on the bundled liver labels: vessels (127, 29
# components), parenchyma (255) and label 85, one mesh per label, in parallel.
case_examples_makefile_one_mesh_per_label() {  # scale
  make -s -f "$SRC/share/examples/Makefile" SCAN="$DATA/liver-labels.nrrd" LABELS="85 127 255" BIN="$BIN/" OUT=ex -j2 \
    RATIO=2 FLAGS="--max-distance 0" 2> make.err || fail "make: $(cat make.err)"
  for l in 85 127 255; do
    "$CHECK" "ex/label-$l.ply" "ex/label-$l.wc.nrrd" 2 > c.txt || fail "example label $l: $(cat c.txt)"
    [[ $(json "ex/label-$l.json" exit_status) == 0 ]] || fail "example label $l: no --stats report"
  done
}

# share/examples/Snakefile over two scans (a folder of label maps), in both
# modes: per label, the Makefile's pipeline; per scan, seg2mesh on the map.
# Scan b is not a's file: the liver's lower 70 slices mirrored left-right,
# raw. Snakemake is a test dependency (scripts/install-deps).
case_snakefile_meshes_every_scan() {  # scale
  command -v snakemake > /dev/null || fail "snakemake is not installed (scripts/install-deps installs it)"
  mkdir scans
  ln -s "$DATA/liver-labels.nrrd" scans/a.nrrd
  python3 - "$DATA/liver-labels.nrrd" scans/b.nrrd <<'P' || fail "cannot write scan b"
import gzip, re, sys
head, data = open(sys.argv[1], 'rb').read().split(b'\n\n', 1)
h = head.decode()
nx, ny, nz = map(int, re.search(r'sizes: *(\d+) (\d+) (\d+)', h).groups())
v = gzip.decompress(data) if 'encoding: gzip' in h else data
nz = 70
out = bytearray()
for r in range(ny * nz):
    out += v[r * nx:(r + 1) * nx][::-1]
h = re.sub(r'sizes: *\d+ \d+ \d+', 'sizes: %d %d %d' % (nx, ny, nz), h)
h = re.sub(r'encoding: *\w+', 'encoding: raw', h)
open(sys.argv[2], 'wb').write(h.encode() + b'\n\n' + bytes(out))
P
  local cfg=(bin="$BIN/" ratio=2 flags="--max-distance 0" labels="85")
  snakemake -q -s "$SRC/share/examples/Snakefile" --cores 2 -d sk \
    --config scans="$PWD/scans" per_label=1 out=lab "${cfg[@]}" > sk.log 2>&1 || fail "Snakefile per label: $(tail -5 sk.log)"
  snakemake -q -s "$SRC/share/examples/Snakefile" --cores 2 -d sk \
    --config scans="$PWD/scans" out=map "${cfg[@]}" > sk.log 2>&1 || fail "Snakefile per scan: $(tail -5 sk.log)"
  for scan in a b; do
    "$BIN/img2wc" -q "scans/$scan.nrrd" --label 85 "wc-$scan.nrrd"
    "$CHECK" "sk/lab/$scan/label-85.ply" "wc-$scan.nrrd" 2 > c.txt || fail "per label, scan $scan: $(cat c.txt)"
    [[ $(json "sk/lab/$scan/label-85.json" exit_status) == 0 ]] || fail "per label, scan $scan: no --stats report"
    [[ $(json "sk/map/$scan.json" exit_status) == 0 ]] || fail "per scan, scan $scan: no --stats report"
    # seg2mesh's surface of label 85 is the per-label pipeline's (same options).
    [[ $(json "sk/map/$scan.json" triangles) == $(json "sk/lab/$scan/label-85.json" triangles) ]] ||
      fail "scan $scan per scan and per label: $(json "sk/map/$scan.json" triangles) and $(json "sk/lab/$scan/label-85.json" triangles) triangles"
  done
  ! cmp -s sk/lab/a/label-85.ply sk/lab/b/label-85.ply || fail "two scans gave one mesh"
}

run_cases "$@"
