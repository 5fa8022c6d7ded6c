#!/usr/bin/env bash
# implicit2tet beside CGAL Mesh_3 on the well-composed labeled image (facet
# angle 30, facet distance 1/4 voxel, cell radius-edge 2, default perturb and
# exude; scripts/bench.d/mesh3_tet_peer.cpp), seeded from every component
# (initialize_triangulation_from_labeled_image + refine_mesh_3, as the
# surface peer) and plain make_mesh_3, and TetGen (`tetgen -pq1.414Y`,
# Debian's binary run as a separate program, never linked: AGPL) on
# implicit2mesh's surface, all at a quarter-voxel distance bound: CPU
# seconds (user + sys, /usr/bin/time: the machine may be shared), peak MB,
# tetrahedra, smallest dihedral angle, share of tetrahedra under 10
# degrees, largest radius-edge ratio, and whether the boundary has the voxel
# boundary's topology (meshinfo --image: by place, component by component).
#   $1: the build's tool folder. BENCH_TET_CASES overrides the cases ("name
# image quarter-voxel [img2wc options] [-- implicit2mesh options]"; image
# "unseen": the case's name is one of debian_data.bash's images the project
# has not been tuned on, e.g. "t1-mask unseen 0.5"); BENCH_TET_CASES=unseen
# runs those four. BENCH_TET_KEEP=DIR keeps every mesh and well-composed image there.
set -euo pipefail
tools=${1:?tool folder}
build=$(cd "$tools/.." && pwd)
src=$(cd "$(dirname "$0")/../.." && pwd)
peer="$build/scripts/bench.d/mesh3_tet_peer"
cmake --build "$build" --target implicit2tet implicit2mesh meshinfo mesh3_tet_peer >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
tetgen=$(command -v tetgen || true)
source "$(dirname "$0")/debian_data.bash"

# timed COMMAND...: runs it, adding its CPU seconds and peak KB to $work/time.
timed() { /usr/bin/time -a -o "$work/time" -f "%U %S %M" "$@"; }
row() {  # row NAME MESH WC: the CPU seconds and peak of the commands timed since the last row
  local status=0
  "$tools/meshinfo" "$2" --image "$3" --json > "$work/info.json" 2>/dev/null || status=$?
  python3 - "$work/info.json" "$1" "$work/time" "$status" <<'PY'
import json, sys
times = [[float(w) for w in l.split()] for l in open(sys.argv[3]) if l.strip() and l[0].isdigit()]
cpu, peak = sum(u + s for u, s, _ in times), max(m for _, _, m in times) / 1024
try:
    r = json.load(open(sys.argv[1]))
except ValueError:
    print("  %-36s %8.1f s   (meshinfo could not read the mesh)" % (sys.argv[2], cpu)); sys.exit()
t = r["tetrahedra"]
ok = "yes" if r["image"]["matches"] and t["conformity"]["conforming"] else "no (%d components, bdCA(X) %d)" % (r["components"], r["image"]["components"])
print("  %-36s %8.1f %7.0f %9d %9.2f %9.2f%% %9.3f   %s" % (sys.argv[2], cpu, peak, t["tetrahedra"], t["min_dihedral_degrees"],
      100 * t["share_dihedral_under_10"], t["max_radius_edge_ratio"], ok))
PY
  rm -f "$work/time"
  [ -z "${BENCH_TET_KEEP:-}" ] || cp "$2" "$3" "$BENCH_TET_KEEP/"
}

# implicit2tet at its defaults but for the distance bound (a quarter voxel,
# as Mesh_3's facet distance); until 2026-12-04 the brain label and the T1
# thresholds ran at --roughness 90, from when the default was 60 degrees.
cases=${BENCH_TET_CASES:-"bunny bunny00-96.nrrd 0.0026
armadillo armadillo-96.nrrd 0.394
liver liver-labels.nrrd 0.1543 --threshold 1
brain3 brain-kmeans-labels.nii.gz 0.5 --label 3"}
[[ $cases == unseen ]] && cases="t1-60 unseen 0.5
t1-100 unseen 0.5
t1-mask unseen 0.5
ct-skull unseen 0.9127"
while read -r name img E rest; do
  [ -n "$name" ] || continue
  wcopts=$rest; meshopts=""
  if [[ " $rest " == *" -- "* ]]; then wcopts=${rest%%-- *}; meshopts=${rest#*-- }; fi
  if [[ $img == unseen ]]; then
    unseen_image "$name" "$work/$name-wc.nrrd" || { echo "implicit2tet.sh: no unseen image $name" >&2; exit 2; }
  else
    # shellcheck disable=SC2086
    "$tools/img2wc" -q "$src/share/data/$img" $wcopts "$work/$name-wc.nrrd"
  fi
  "$tools/wc2implicit" -q "$work/$name-wc.nrrd" "$work/$name-f.nrrd"
  echo "$name ($img $wcopts, distance bound $E = 1/4 voxel):"
  printf "  %-36s %8s %7s %9s %9s %10s %9s   %s\n" "mesher" "CPU s" "peak MB" "tets" "min dih" "<10 deg" "max ratio" "topology ok"
  # shellcheck disable=SC2086
  timed "$tools/implicit2tet" -q "$work/$name-f.nrrd" "$work/$name.msh" --max-distance "$E" $meshopts || true
  row "implicit2tet" "$work/$name.msh" "$work/$name-wc.nrrd"
  # shellcheck disable=SC2086
  timed "$tools/implicit2tet" -q "$work/$name-f.nrrd" "$work/$name-0.msh" --max-distance "$E" --sliver-angle 0 $meshopts || true
  row "implicit2tet --sliver-angle 0" "$work/$name-0.msh" "$work/$name-wc.nrrd"
  timed "$peer" "$work/$name-wc.nrrd" "$work/$name-mesh3s.mesh" seeded > /dev/null
  row "CGAL Mesh_3 seeded, every component" "$work/$name-mesh3s.mesh" "$work/$name-wc.nrrd"
  timed "$peer" "$work/$name-wc.nrrd" "$work/$name-mesh3.mesh" plain > /dev/null
  row "CGAL make_mesh_3" "$work/$name-mesh3.mesh" "$work/$name-wc.nrrd"
  if [ -n "$tetgen" ]; then
    # shellcheck disable=SC2086
    timed "$tools/implicit2mesh" -q "$work/$name-f.nrrd" "$work/$name-s.off" --max-distance "$E" $meshopts || true
    timed "$tetgen" -pq1.414Yg "$work/$name-s.off" > "$work/tetgen.log" 2>&1 || { tail -3 "$work/tetgen.log"; rm -f "$work/time"; continue; }
    row "implicit2mesh + tetgen -pq1.414Y" "$work/$name-s.1.mesh" "$work/$name-wc.nrrd"
  else
    echo "  tetgen: not installed (apt-get install tetgen), skipped"
  fi
done <<< "$cases"
