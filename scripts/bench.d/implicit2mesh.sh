#!/usr/bin/env bash
# implicit2mesh: time and size at rho_0 = 2, 1.5, 1.2 on the bundled real
# images, and CGAL's Surface_mesher (make_surface_mesh, 30-degree angle bound,
# Manifold_tag) on the same implicit function f, side by side: time,
# triangles, smallest angle, largest radius-edge ratio, topology equal to the
# voxel boundary bdCA(X') or not, and max |f| at the triangles' centroids
# (f ~ signed distance: a geometric error estimate).   $1: the build's tool folder.
set -euo pipefail
tools=${1:?tool folder}
build=$(cd "$tools/.." && pwd)
src=$(cd "$(dirname "$0")/../.." && pwd)
check="$build/tests/unit/surface/surface_check"
peer="$build/scripts/bench.d/surface_mesher_peer"
cmake --build "$build" --target surface_check surface_mesher_peer >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

row() {  # row NAME MESH WC SECONDS BOUND MAX|f|-AT-CENTROIDS
  local line status=yes
  line=$("$check" "$2" "$3" "$5") || status=no
  awk -v name="$1" -v secs="$4" -v ok="$status" -v err="$6" '{
    for (i = 1; i <= NF; ++i) { if ($i == "triangles") t = $(i+1); if ($i == "max_ratio") r = $(i+1); if ($i == "min_angle_deg") a = $(i+1) }
    printf "  %-34s %8.2f s %9d %9.2f %9.3f %9.3f   %s\n", name, secs, t, a, r, err, ok }' <<< "$line"
}
centroid_error() { grep -o '"max_abs_f_at_centroids": [0-9.e+-]*' "$1" | awk '{print $2}'; }

# A generated "Swiss cheese" (a block with two tunnels and six cavities: seven
# components, Euler characteristics -2 and 2 x 6), where topology is hard.
awk 'BEGIN {
  n = 40; print "NRRD0004"; print "type: uint8"; print "dimension: 3"
  print "sizes: " n " " n " " n; print "spacings: 1 1 1"; print "encoding: ascii"; print ""
  split("12.3 11.6 12.2 27.4 12.1 11.8 12.2 27.7 12.4 27.9 27.3 12.1 12.6 12.2 27.6 27.2 27.8 27.5", c, " ")
  for (z = 0; z < n; z++) for (y = 0; y < n; y++) for (x = 0; x < n; x++) {
    v = (x >= 3 && x <= 36 && y >= 3 && y <= 36 && z >= 3 && z <= 36)
    if ((x - 20)^2 + (y - 20)^2 < 9 || (y - 20)^2 + (z - 30)^2 < 6) v = 0
    for (k = 0; k < 6; k++) if ((x - c[3*k+1])^2 + (y - c[3*k+2])^2 + (z - c[3*k+3])^2 < 9) v = 0
    printf "%d\n", v
  } }' > "$work/cheese.nrrd"

for img in bunny00-96 elephant-96 armadillo-96 cheese; do
  # A quarter voxel in world units (the images' spacings), as the peer's bound.
  case $img in bunny*) E=0.0026;; elephant*) E=0.0026;; armadillo*) E=0.394;; *) E=0.25;; esac
  data="$src/share/data/$img.nrrd"
  [ -f "$data" ] || data="$work/$img.nrrd"
  "$tools/img2wc" -q "$data" "$work/$img-wc.nrrd"
  "$tools/wc2implicit" -q "$work/$img-wc.nrrd" "$work/$img-f.nrrd"
  echo "$img:"
  printf "  %-34s %10s %9s %9s %9s %9s   %s\n" "mesher" "time" "triangles" "min angle" "max ratio" "max |f|" "topology ok"
  for r in 2 1.5 1.2; do
    start=$(date +%s.%N)
    "$tools/implicit2mesh" -q "$work/$img-f.nrrd" "$work/$img-$r.off" --ratio "$r" --stats "$work/s.json" || true
    secs=$(echo "$(date +%s.%N) - $start" | bc)
    row "implicit2mesh --ratio $r" "$work/$img-$r.off" "$work/$img-wc.nrrd" "$secs" "$r" "$(centroid_error "$work/s.json")"
  done
  start=$(date +%s.%N)
  "$tools/implicit2mesh" -q "$work/$img-f.nrrd" "$work/$img-d.off" --max-distance "$E" --stats "$work/s.json" || true
  secs=$(echo "$(date +%s.%N) - $start" | bc)
  row "implicit2mesh --max-distance 1/4 vx" "$work/$img-d.off" "$work/$img-wc.nrrd" "$secs" 2 "$(centroid_error "$work/s.json")"
  # Surface_mesher: no size bound, distance bound 0.25 voxel.
  for d in 0.25; do
    if out=$(timeout 600 "$peer" "$work/$img-f.nrrd" "$work/$img-peer.off" 0 "$d"); then
      read -r psecs ptris perr <<< "$out"
      row "CGAL Surface_mesher dist. $d vx" "$work/$img-peer.off" "$work/$img-wc.nrrd" "$psecs" 1000 "$perr"
    else
      echo "  CGAL Surface_mesher dist. $d vx: failed or timed out (600 s)"
    fi
  done
done

# Real tissue: two classes of the bundled brain k-means segmentation (noisy:
# hundreds of components, genus in the hundreds) and CGAL's liver CT labels
# (whole organ: 35 components), at the default roughness pi/3 and at pi/2,
# beside CGAL's Surface_mesher on the same f.
for case in "brain3 brain-kmeans-labels.nii.gz --label 3" "brain4 brain-kmeans-labels.nii.gz --label 4" \
            "liver liver-labels.nrrd --threshold 1"; do
  read -r name file sel <<< "$case"
  # shellcheck disable=SC2086  # $sel is an option and its value
  "$tools/img2wc" -q "$src/share/data/$file" $sel "$work/$name-wc.nrrd"
  "$tools/wc2implicit" -q "$work/$name-wc.nrrd" "$work/$name-f.nrrd"
  echo "$file, $sel:"
  printf "  %-34s %10s %9s %9s %9s %9s   %s\n" "mesher" "time" "triangles" "min angle" "max ratio" "max |f|" "topology ok"
  for g in 1.0471975511965976 1.5707963267948966; do
    start=$(date +%s.%N)
    "$tools/implicit2mesh" -q "$work/$name-f.nrrd" "$work/$name-$g.off" --roughness "$g" --stats "$work/s.json" || true
    secs=$(echo "$(date +%s.%N) - $start" | bc)
    row "implicit2mesh --roughness ${g:0:6}" "$work/$name-$g.off" "$work/$name-wc.nrrd" "$secs" 2 "$(centroid_error "$work/s.json")"
  done
  if out=$(timeout 600 "$peer" "$work/$name-f.nrrd" "$work/$name-peer.off" 0 0.25); then
    read -r psecs ptris perr <<< "$out"
    row "CGAL Surface_mesher dist. 0.25 vx" "$work/$name-peer.off" "$work/$name-wc.nrrd" "$psecs" 1000 "$perr"
  else
    echo "  CGAL Surface_mesher dist. 0.25 vx: failed or timed out (600 s)"
  fi
done
