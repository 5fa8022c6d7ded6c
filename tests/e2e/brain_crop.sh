#!/bin/bash
# implicit2mesh on real tissue that fills its grid: a 24 x 24 x 16 crop of
# the bundled brain k-means class 5 (anisotropic 2 x 2 x 3 mm voxels, a
# rotated frame) whose tissue touches every face of the crop, so that after
# img2wc's padding S runs one voxel from the grid's border on every side.
# The mesh must have the topology of the crop's voxel boundary, component by
# component and by place (meshinfo --image), be certified by the mesher with
# no repair and no refused TOPOLOGY insertion, within 5 minutes.
source "$(dirname "$0")/lib.sh"

crop_py() {  # crop_py FULL CROP: the crop, refused unless tissue is on every face
  python3 - "$1" "$2" <<'P'
import gzip, re, sys
head, data = open(sys.argv[1], 'rb').read().split(b'\n\n', 1)
h = head.decode()
nx, ny, nz = map(int, re.search(r'sizes: *(\d+) (\d+) (\d+)', h).groups())
v = gzip.decompress(data) if 'encoding: gzip' in h else data
x0, y0, z0, W, D = 52, 52, 23, 24, 16
out = bytearray()
for z in range(z0, z0 + D):
    for y in range(y0, y0 + W):
        row = (z * ny + y) * nx
        out += v[row + x0:row + x0 + W]
at = lambda x, y, z: out[(z * W + y) * W + x]
faces = [any(at(0, y, z) for y in range(W) for z in range(D)), any(at(W - 1, y, z) for y in range(W) for z in range(D)),
         any(at(x, 0, z) for x in range(W) for z in range(D)), any(at(x, W - 1, z) for x in range(W) for z in range(D)),
         any(at(x, y, 0) for x in range(W) for y in range(W)), any(at(x, y, D - 1) for x in range(W) for y in range(W))]
if not all(faces): sys.exit('the crop leaves a face free: %r' % faces)
hdr = re.sub(r'sizes: *\d+ \d+ \d+', 'sizes: %d %d %d' % (W, W, D), h)
hdr = re.sub(r'encoding: *\w+', 'encoding: raw', hdr)
open(sys.argv[2], 'wb').write(hdr.encode() + b'\n\n' + bytes(out))
P
}
# crop-wc.nrrd and crop-f.nrrd: the crop made well-composed, and its f
# (crop_py cuts at the scan's indices: img2wc's whole grid).
crop_f() {
  expect 0 img2wc "$DATA/brain-kmeans-labels.nii.gz" --label 5 --full-grid full.nrrd -q &&
    expect 0 crop_py full.nrrd crop.nrrd &&
    expect 0 img2wc crop.nrrd --threshold 1 crop-wc.nrrd -q &&
    expect 0 wc2implicit crop-wc.nrrd crop-f.nrrd -q && rm -f full.nrrd crop.nrrd
}

# certified ROUGHNESS [OPTIONS...]: the crop meshed, certified with no repair
# and no refusal, in under 5 minutes, and matching the voxel boundary by place.
certified() {
  local r=$1 f wc; shift
  f=$(shared crop-f.nrrd crop_f) || return
  wc=$(dirname "$f")/crop-wc.nrrd
  local start=$SECONDS
  expect 0 implicit2mesh "$f" crop.off --stats crop.json -q "$@" || return
  ((SECONDS - start < 300)) || fail "roughness $r: took $((SECONDS - start)) s (5 minutes at most)"
  [[ $(json crop.json topology_matches) == True ]] || fail "roughness $r: not certified"
  [[ $(json crop.json topology_fallback_rounds) == 0 ]] || fail "roughness $r: the fallback acted"
  [[ $(json crop.json topology_fallback_points) == 0 ]] || fail "roughness $r: the fallback inserted points"
  [[ $(json crop.json topology_insertions_refused) == 0 ]] || fail "roughness $r: TOPOLOGY insertions refused"
  OUT=info.txt expect 0 meshinfo crop.off --image "$wc" -q || return
  grep -q "MATCHES" info.txt || fail "roughness $r: $(cat info.txt)"
}

case_tissue_on_every_face_certified_at_the_defaults() {
  certified default || return
  # The crop's boundary is not trivial: more than one component.
  OUT=info.json expect 0 meshinfo --json crop.off || return
  (($(json info.json components) >= 2)) || fail "the crop's mesh has a single component"
}

case_tissue_on_every_face_certified_at_roughness_60() { certified 60 --roughness 60; }

run_cases "$@"
