#!/usr/bin/env bash
# img2wc --label's crops (the label's box plus a margin, placed back in the
# scan by the frame its NRRD carries): the same meshes as the scan's whole
# grid (img2wc --full-grid), the same triangles and every vertex within
# 1e-9 in world coordinates, at the cost of the label's box.
source "$(dirname "$0")/lib.sh"

# same_mesh A B: the same triangles, every vertex within 1e-9 (world units).
same_mesh() {
  python3 - "$1" "$2" "$E2E" > cmp.txt 2>&1 <<'PY' || fail "$1 and $2 differ: $(cat cmp.txt)"
import sys; sys.path.insert(0, sys.argv[3]); import surface_read as r
a, b = r.read(sys.argv[1]), r.read(sys.argv[2])
assert len(a['triangles']) > 0, 'no triangles'
assert a['triangles'] == b['triangles'], 'the triangles differ (%d and %d)' % (len(a['triangles']), len(b['triangles']))
assert len(a['points']) == len(b['points']), 'the vertices differ in number'
d = max(abs(x - y) for p, q in zip(a['points'], b['points']) for x, y in zip(p, q))
assert d <= 1e-9, 'a vertex moved by %g' % d
PY
}

# pipeline IMAGE LABEL NAME [IMG2WC OPTIONS]: NAME-wc.nrrd, NAME-f.nrrd and
# NAME.off through the three tools (the mesher at its defaults, --threads 1).
pipeline() {
  local img=$1 L=$2 name=$3; shift 3
  expect 0 img2wc "$img" --label "$L" "$name-wc.nrrd" -q "$@" &&
    expect 0 wc2implicit "$name-wc.nrrd" "$name-f.nrrd" -q &&
    expect 0 implicit2mesh "$name-f.nrrd" "$name.off" -q --threads 1
}

# A label's crop and the whole grid: the same mesh, a smaller implicit file.
crop_is_full_grid() {
  local img=$1 L=$2
  pipeline "$img" "$L" crop && pipeline "$img" "$L" full --full-grid || return
  same_mesh crop.off full.off
  (($(stat -c %s crop-f.nrrd) < $(stat -c %s full-f.nrrd))) || fail "label $L: the crop's file is not smaller"
}

case_bundled_liver_label_meshes_as_the_full_grid() {  # scale
  crop_is_full_grid "$DATA/liver-labels.nrrd" 85
}

# big.nrrd: a 220x200x90 label map (0.8 x 0.8 x 1.5 mm, a frame rotated by
# 25 degrees about z, far from the origin): label 1 a large slab, label 7 a
# ball of about a hundred voxels near the far corner.
big_map() {
  python3 - <<'PY'
import math
N = (220, 200, 90)
a = math.radians(25)
D = [[0.8 * math.cos(a), -0.8 * math.sin(a), 0], [0.8 * math.sin(a), 0.8 * math.cos(a), 0], [0, 0, 1.5]]  # columns: axes
body = bytearray(N[0] * N[1] * N[2])
for z in range(10, 50):
    for y in range(20, 120):
        o = (z * N[1] + y) * N[0]
        body[o + 15:o + 140] = b'\x01' * 125
for z in range(70, 84):
    for y in range(180, 196):
        for x in range(196, 212):
            if (x - 204.3) ** 2 + (y - 188.1) ** 2 + ((z - 77.2) * 1.8) ** 2 <= 30:
                body[(z * N[1] + y) * N[0] + x] = 7
dirs = ' '.join('(%r,%r,%r)' % (D[0][c], D[1][c], D[2][c]) for c in range(3))
open('big.nrrd', 'wb').write(('NRRD0004\ntype: uint8\ndimension: 3\nspace: left-posterior-superior\n'
    'sizes: %d %d %d\nspace directions: %s\nspace origin: (1234.5,-987.25,640.125)\nencoding: raw\n\n'
    % (N + (dirs,))).encode() + bytes(body))
PY
}

# A tiny label far from the origin of a big grid: the whole grid's mesh,
# from an implicit file under 1 MB (the whole grid's is 15 MB).
case_tiny_label_far_from_the_origin_of_a_big_grid() {
  local big; big=$(shared big.nrrd big_map) || return
  pipeline "$big" 7 crop --stats crop-wc.json && pipeline "$big" 7 full --full-grid || return
  same_mesh crop.off full.off
  local bytes; bytes=$(stat -c %s crop-f.nrrd)
  ((bytes < 1000000)) || fail "the crop's implicit file takes $bytes bytes"
  python3 - <<'PY' > py.txt 2>&1 || fail "img2wc's crop: $(tail -1 py.txt)"
import json
s = json.load(open('crop-wc.json'))
assert s['scan_size'] == [220, 200, 90], s['scan_size']
n = s['output_size']
assert n[0] * n[1] * n[2] < 10000, n  # the scan: 3,960,000
PY
  # implicit2tet, --outside too (its box is the scan's): the same tetrahedra.
  expect 0 implicit2tet crop-f.nrrd crop.mesh -q --outside --cell-ratio 3 &&
    expect 0 implicit2tet full-f.nrrd full.mesh -q --outside --cell-ratio 3 || return
  cmp -s crop.mesh full.mesh || fail "implicit2tet --outside: the crop's tetrahedra differ from the whole grid's"
}

# Through pipes: the crop's frame travels on standard output and input.
case_pipes_carry_the_crop() {
  local big; big=$(shared big.nrrd big_map) || return
  "$BIN/img2wc" -q "$big" --label 7 - | "$BIN/wc2implicit" -q - - | "$BIN/implicit2mesh" -q --threads 1 - pipe.off
  [[ ${PIPESTATUS[*]} == "0 0 0" ]] || { fail "the pipeline failed: ${PIPESTATUS[*]}"; return; }
  pipeline "$big" 7 full --full-grid && same_mesh pipe.off full.off
}

# A --max-distance beyond what the margin covers: the crop meshed on its own
# grid, said on stderr, the surface still certified against its voxels.
case_max_distance_beyond_the_margin_meshes_the_crop_alone() {
  local big; big=$(shared big.nrrd big_map) || return
  # g whole (--full-distance): a clamp beyond the margin, so the crop's own grid.
  expect 0 img2wc "$big" --label 7 crop-wc.nrrd -q && expect 0 wc2implicit crop-wc.nrrd crop-f.nrrd -q --full-distance &&
    expect 0 implicit2mesh crop-f.nrrd crop.off --max-distance 3 || return
  grep -q "margin does not cover" err.txt || fail "no note on stderr: $(cat err.txt)"
  OUT=info.txt expect 0 meshinfo crop.off --image crop-wc.nrrd -q && grep -q MATCHES info.txt ||
    fail "not certified: $(cat info.txt)"
  # The default narrow band: meshed on its clamped samples, in the scan's frame.
  expect 0 wc2implicit crop-wc.nrrd band-f.nrrd -q && expect 0 implicit2mesh band-f.nrrd band.off --max-distance 3 || return
  grep -q "clamped for a --max-distance up to 0.5 voxel" err.txt || fail "no note on stderr: $(cat err.txt)"
  grep -q "margin does not cover" err.txt && fail "the band's clamp is within the margin: $(cat err.txt)"
  OUT=info.txt expect 0 meshinfo band.off --image crop-wc.nrrd -q && grep -q MATCHES info.txt ||
    fail "not certified: $(cat info.txt)"
  [[ $(stat -c %s band-f.nrrd) -lt $(stat -c %s crop-f.nrrd) ]] || fail "the band's file is no smaller than g whole"
}

run_cases "$@"
