#!/usr/bin/env bash
# Multi-material tetrahedra (issue 41) side by side, one run per map: our
# seg2tet (experimental) and CGAL Mesh_3 on the same label map
# (mesh3_labels_peer.cpp with a tetrahedral OUT: seeded from every component
# of every label, facet angle 30, facet distance 1/4 voxel, cell radius-edge
# ratio 2, Mesh_3's default perturb and exude). Maps: the bundled brain map
# and a synthetic head (labelmap.py head, fixed seed) of HEAD_SIZE^3 voxels
# (default 64). Per mesher: wall and CPU seconds, peak memory, tetrahedra,
# smallest dihedral angle, share of tetrahedra with one under 10 degrees,
# largest radius-edge ratio; ours also its certificate's verdict (Mesh_3's
# output is not certified here: meshinfo certifies one region against a
# binary image, not a label map's regions).
# On a shared machine compare the CPU seconds: wall time grows with the load.
#   $1: the build's tool folder. BENCH_MAPS (default "head brain"),
#   HEAD_SIZE, MESH3_TIMEOUT (default 1800 s).
set -euo pipefail
tools=${1:?tool folder}
build=$(cd "$tools/.." && pwd)
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
peer="$build/scripts/bench.d/mesh3_labels_peer"
cmake --build "$build" --target seg2tet mesh3_labels_peer > /dev/null
maps=${BENCH_MAPS:-head brain}
limit=${MESH3_TIMEOUT:-1800}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

timed() {  # timed CMD...: prints "wall cpu peak_MB" of CMD, its output in $work/run.out
  local rc=0
  /usr/bin/time -f "%e %U %S %M" -o "$work/time" "$@" > "$work/run.out" 2> "$work/run.err" || rc=$?
  read -r wall user sys mem < <(tail -1 "$work/time")
  printf "%7.1f %7.1f %7.0f" "$wall" "$(echo "$user + $sys" | bc)" "$(echo "$mem / 1024" | bc)"
  [ "$rc" -eq 0 ] || echo -n "  (exit $rc: $(tail -1 "$work/run.err"))" >&2
}

printf "  %-6s %-22s %7s %7s %7s %11s %9s %8s %9s  %s\n" map mesher wall_s cpu_s peak_MB tetrahedra min_dihed under_10 max_ratio certified
for m in $maps; do
  case $m in
    brain) img=$src/share/data/brain-kmeans-labels.nii.gz ;;
    head) img=$work/head.mha; /usr/bin/python3 "$here/labelmap.py" head "$img" "${HEAD_SIZE:-64}" ;;
    *) echo "seg2tet.sh: unknown map $m" >&2; exit 2 ;;
  esac
  t=$(timed "$tools/seg2tet" -q "$img" "$work/$m.msh" --stats "$work/$m.json")
  /usr/bin/python3 - "$work/$m.json" "$m" "$t" <<'P'
import json, sys
s = json.load(open(sys.argv[1])); t = s['tetrahedra']; q = t['quality']
verdict = 'yes' if s['all_certified'] else 'no: ' + s['certificate'].get('failure', '')[:60]
print("  %-6s %-22s %s %11d %9.2f %7.2f%% %9.2f  %s" % (sys.argv[2], 'seg2tet', sys.argv[3], t['tetrahedra'],
      q['min_dihedral_degrees'], 100 * q['share_dihedral_under_10'], q['max_radius_edge_ratio'], verdict))
P
  t=$(timed timeout "$limit" "$peer" "$img" "$work/$m-m3.msh" 0.25)
  read -r secs tets dihed share ratio < <(tail -1 "$work/run.out")
  printf "  %-6s %-22s %s %11d %9.2f %7.2f%% %9.2f  %s\n" "$m" "CGAL Mesh_3 (own ${secs%.*} s)" "$t" "$tets" "$dihed" \
    "$(echo "100 * $share" | bc -l)" "$ratio" "not checked"
done
