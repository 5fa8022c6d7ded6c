#!/usr/bin/env bash
# implicit2mesh at its defaults beside its peers, one table in one run
# (and beside itself with --no-voxel-sides, issue 38's cost):
# CGAL Mesh_3 on the labeled (well-composed) image, seeded from every
# component (initialize_triangulation_from_labeled_image, then refine_mesh_3)
# and plain make_mesh_3 (facet angle 30, distance 1/4 voxel, manifold), CGAL
# Surface_mesher on the same f (angle 30, distance 1/4 voxel, manifold), and
# ITK marching cubes (BinaryMask3DMeshSource) on the well-composed image.
# Columns: wall seconds (CPU seconds, user + system: the fairer clock on a
# shared machine), triangles, smallest angle, max |f| at the triangles'
# centroids in voxels, largest normal jump between triangles sharing an
# edge, topology equal to the voxel boundary (meshinfo --image), peak RSS of
# the process (/usr/bin/time -v). Ours is implicit2mesh alone (wc2implicit's
# time, f for implicit2mesh and Surface_mesher, is printed per image).
#   $1: the build's tool folder. IMPLICIT2MESH_IMAGES: which images (default
#   all bundled): bunny elephant armadillo liver brain1 .. brain5 cheese, and
#   images the project has not been tuned on, fetched from Debian packages
#   (debian_data.bash): t1-60 t1-100 t1-mask ct-skull; IMPLICIT2MESH_IMAGES=unseen
#   runs those four; e.g. IMPLICIT2MESH_IMAGES="bunny brain3" scripts/bench implicit2mesh.
set -euo pipefail
tools=${1:?tool folder}
build=$(cd "$tools/.." && pwd)
src=$(cd "$(dirname "$0")/../.." && pwd)
peers="$build/scripts/bench.d"
cmake --build "$build" --target implicit2mesh img2wc wc2implicit implicit-eval meshinfo \
  surface_mesher_peer mesh3_peer marching_cubes_peer >/dev/null
images=${IMPLICIT2MESH_IMAGES:-bunny elephant armadillo liver brain1 brain2 brain3 brain4 brain5}
[[ $images == unseen ]] && images="t1-60 t1-100 t1-mask ct-skull"
source "$(dirname "$0")/debian_data.bash"
limit=${IMPLICIT2MESH_TIMEOUT:-1800}  # seconds a peer may take
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# A generated "Swiss cheese" (a block with two tunnels and six cavities: seven
# components, Euler characteristics -2 and 2 x 6), where topology is hard.
cheese() {
  awk 'BEGIN {
    n = 40; print "NRRD0004"; print "type: uint8"; print "dimension: 3"
    print "sizes: " n " " n " " n; print "spacings: 1 1 1"; print "encoding: ascii"; print ""
    split("12.3 11.6 12.2 27.4 12.1 11.8 12.2 27.7 12.4 27.9 27.3 12.1 12.6 12.2 27.6 27.2 27.8 27.5", c, " ")
    for (z = 0; z < n; z++) for (y = 0; y < n; y++) for (x = 0; x < n; x++) {
      v = (x >= 3 && x <= 36 && y >= 3 && y <= 36 && z >= 3 && z <= 36)
      if ((x - 20)^2 + (y - 20)^2 < 9 || (y - 20)^2 + (z - 30)^2 < 6) v = 0
      for (k = 0; k < 6; k++) if ((x - c[3*k+1])^2 + (y - c[3*k+2])^2 + (z - c[3*k+3])^2 < 9) v = 0
      printf "%d\n", v
    } }' > "$1"
}

# run TAG NAME MESH COMMAND...: COMMAND's wall time and peak RSS, then the row.
# BENCH_REPEAT=N runs it N times and keeps the median CPU time (one run's
# CPU time moves by up to 30% on this kind of machine; the meshes do not).
run() {
  local tag=$1 name=$2 mesh=$3; shift 3
  local rc r secs user sys kb cpus=()
  for ((r = 0; r < ${BENCH_REPEAT:-1}; ++r)); do
    rc=0
    rm -f "$mesh"
    nice timeout "$limit" /usr/bin/time -f '%e %U %S %M' -o "$work/time" "$@" > "$work/out" 2> "$work/err" || rc=$?
    if [[ ! -s $mesh ]] || { [[ $rc -ne 0 && $rc -ne 3 ]]; }; then
      printf '| %s | %s | failed (exit %d%s) | | | | | | |\n' "$img" "$name" "$rc" \
        "$([[ $rc -eq 124 ]] && echo ", over $limit s")"
      return
    fi
    read -r secs user sys kb < <(tail -1 "$work/time")
    cpus+=("$(echo "$user + $sys" | bc)")
  done
  local cpu
  cpu=$(printf '%s\n' "${cpus[@]}" | sort -g | sed -n "$(((${#cpus[@]} + 1) / 2))p")
  read -r tris angle jump err < <(/usr/bin/python3 "$src/scripts/bench.d/mesh_metrics.py" "$mesh" "$work/f.nrrd" "$tools/implicit-eval")
  local topo=wrong
  "$tools/meshinfo" -q --image "$work/wc.nrrd" "$mesh" > /dev/null 2>&1 && topo=right
  printf '| %s | %s | %.1f (%.1f) | %d | %.1f | %.2f | %.0f | %s | %.0f |\n' "$img" "$name" "$secs" "$cpu" "$tris" "$angle" "$err" \
    "$jump" "$topo" "$((kb / 1024))"
  echo "$img $tag $cpu $tris $kb" >> "$work/summary"
}

echo "| image | mesher | wall s (CPU s) | triangles | min angle (deg) | max \|f\| at centroids (voxels) | max normal jump (deg) | topology | peak MB |"
echo "|---|---|---|---|---|---|---|---|---|"
for img in $images; do
  case $img in
    bunny) "$tools/img2wc" -q "$src/share/data/bunny00-96.nrrd" "$work/wc.nrrd" ;;
    elephant|armadillo) "$tools/img2wc" -q "$src/share/data/$img-96.nrrd" "$work/wc.nrrd" ;;
    liver) "$tools/img2wc" -q "$src/share/data/liver-labels.nrrd" --threshold 1 "$work/wc.nrrd" ;;
    brain[1-5]) "$tools/img2wc" -q "$src/share/data/brain-kmeans-labels.nii.gz" --label "${img#brain}" "$work/wc.nrrd" ;;
    cheese) cheese "$work/cheese.nrrd"; "$tools/img2wc" -q "$work/cheese.nrrd" "$work/wc.nrrd" ;;
    *) unseen_image "$img" "$work/wc.nrrd" || { echo "implicit2mesh.sh: unknown image $img" >&2; exit 2; } ;;
  esac
  /usr/bin/time -f '%e' -o "$work/time" "$tools/wc2implicit" -q "$work/wc.nrrd" "$work/f.nrrd"
  echo "$img f $(tail -1 "$work/time")" >> "$work/summary"
  run ours "implicit2mesh (defaults)" "$work/ours.off" "$tools/implicit2mesh" -q "$work/f.nrrd" "$work/ours.off"
  run off "implicit2mesh --no-voxel-sides" "$work/off.off" "$tools/implicit2mesh" -q --no-voxel-sides "$work/f.nrrd" "$work/off.off"
  run m3s "CGAL Mesh_3, seeded from every component" "$work/m3s.off" "$peers/mesh3_peer" "$work/wc.nrrd" "$work/m3s.off" seeded
  run m3p "CGAL make_mesh_3" "$work/m3p.off" "$peers/mesh3_peer" "$work/wc.nrrd" "$work/m3p.off" plain
  run sm "CGAL Surface_mesher, same f" "$work/sm.off" "$peers/surface_mesher_peer" "$work/f.nrrd" "$work/sm.off" 0 0.25
  run mc "ITK marching cubes" "$work/mc.off" "$peers/marching_cubes_peer" "$work/wc.nrrd" "$work/mc.off"
done
# Per image: ours against the Done-when marks of issues 17 and 38 (the
# last two columns: the defaults over --no-voxel-sides).
echo
echo "| image | wc2implicit s | CPU time / Mesh_3 seeded | triangles / marching cubes | peak bytes per triangle | triangles / --no-voxel-sides | CPU / --no-voxel-sides |"
echo "|---|---|---|---|---|---|---|"
awk 'function r(a, b) { return (a != "" && b) ? sprintf("%.2f", a / b) : "-" }
     $2 == "f" { f[$1] = $3; order[++n] = $1 } $2 == "ours" { os[$1] = $3; ot[$1] = $4; ok[$1] = $5 }
     $2 == "off" { fs[$1] = $3; ft[$1] = $4 } $2 == "m3s" { ms[$1] = $3 } $2 == "mc" { mt[$1] = $4 }
     END { for (i = 1; i <= n; ++i) { k = order[i]
       printf "| %s | %.1f | %s | %s | %s | %s | %s |\n", k, f[k], r(os[k], ms[k]), r(ot[k], mt[k]),
         ot[k] ? sprintf("%.0f", ok[k] * 1024 / ot[k]) : "-", (ot[k] && ft[k]) ? sprintf("%.3f", ot[k] / ft[k]) : "-", r(os[k], fs[k]) } }' \
  "$work/summary"
