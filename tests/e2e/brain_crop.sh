#!/bin/bash
# implicit2mesh on real tissue that fills its grid: a 24 x 24 x 16 crop of
# the bundled brain k-means class 5 (anisotropic 2 x 2 x 3 mm voxels, a
# rotated frame) whose tissue touches every face of the crop, so that after
# img2wc's padding S runs one voxel from the grid's border on every side.
# The mesh must have the topology of the crop's voxel boundary, component by
# component and by place (meshinfo --image), and be certified by the mesher.
set -euo pipefail
mkdir -p "$TMP"
cd "$TMP"
rm -rf ./*
fail() { echo "FAIL: $*" >&2; exit 1; }
for t in img2wc wc2implicit implicit2mesh meshinfo; do [ -x "$BIN/$t" ] || fail "no $BIN/$t"; done

"$BIN/img2wc" -q "$DATA/brain-kmeans-labels.nii.gz" --label 5 full.nrrd
python3 - full.nrrd crop.nrrd <<'P'
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
# Tissue on every face of the crop.
at = lambda x, y, z: out[(z * W + y) * W + x]
faces = [any(at(0, y, z) for y in range(W) for z in range(D)), any(at(W - 1, y, z) for y in range(W) for z in range(D)),
         any(at(x, 0, z) for x in range(W) for z in range(D)), any(at(x, W - 1, z) for x in range(W) for z in range(D)),
         any(at(x, y, 0) for x in range(W) for y in range(W)), any(at(x, y, D - 1) for x in range(W) for y in range(W))]
if not all(faces): sys.exit('the crop leaves a face free: %r' % faces)
hdr = re.sub(r'sizes: *\d+ \d+ \d+', 'sizes: %d %d %d' % (W, W, D), h)
hdr = re.sub(r'encoding: *\w+', 'encoding: raw', hdr)
open(sys.argv[2], 'wb').write(hdr.encode() + b'\n\n' + bytes(out))
P
"$BIN/img2wc" -q crop.nrrd --threshold 1 crop-wc.nrrd
"$BIN/wc2implicit" -q crop-wc.nrrd crop-f.nrrd
for r in default 60; do
  opt=(); [ "$r" = default ] || opt=(--roughness "$r")
  "$BIN/implicit2mesh" -q crop-f.nrrd "crop-$r.off" "${opt[@]}" --stats "crop-$r.json" || fail "implicit2mesh at roughness $r: exit $?"
  grep -q '"topology_matches": true' "crop-$r.json" || fail "roughness $r: not certified"
  grep -q '"topology_fallback_rounds": 0' "crop-$r.json" || fail "roughness $r: the fallback acted"
  grep -q '"topology_insertions_refused": 0' "crop-$r.json" || fail "roughness $r: TOPOLOGY insertions refused"
  "$BIN/meshinfo" -q "crop-$r.off" --image crop-wc.nrrd > "info-$r.txt" || fail "roughness $r: meshinfo --image: exit $?"
  grep -q "MATCHES" "info-$r.txt" || fail "roughness $r: $(cat "info-$r.txt")"
done
# The crop's boundary is not trivial (16 components, one of genus 77).
"$BIN/meshinfo" --json crop-default.off | python3 -c 'import json,sys; n = json.load(sys.stdin)["components"]; sys.exit(0 if n >= 2 else "one component only")' \
  || fail "the crop's mesh has a single component"
echo "brain crop e2e: ok"
