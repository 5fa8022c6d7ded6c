#!/usr/bin/env bash
# Multi-material tetrahedra (issue 41) side by side, one run per map: our
# seg2tet (experimental) and CGAL Mesh_3 on the same label map
# (mesh3_labels_peer.cpp with a tetrahedral OUT: seeded from every component
# of every label, facet angle 30, facet distance 1/4 voxel, cell radius-edge
# ratio 2, Mesh_3's default perturb and exude). Maps: the bundled brain map
# and a synthetic head (labelmap.py head, fixed seed; head2: with holes
# through the skull and a tube through four tissues) of HEAD_SIZE^3 voxels
# (default 64). Per mesher: wall and CPU seconds, peak memory, tetrahedra,
# smallest dihedral angle, share of tetrahedra with one under 10 degrees,
# largest radius-edge ratio, and the certificate's verdict: ours its own
# and meshinfo's, Mesh_3's meshinfo's (meshinfo TETS --image LABELS: the
# map repaired as seg2tet repairs it, every tetrahedron positive, conforming,
# a region per label, every voxel centre in a tetrahedron of its label, the
# regions' interfaces through the interface certificate).
# On a shared machine compare the CPU seconds: wall time grows with the load.
#   $1: the build's tool folder. BENCH_MAPS (default "head brain"),
#   HEAD_SIZE, MESH3_TIMEOUT (default 1800 s).
set -euo pipefail
tools=${1:?tool folder}
build=$(cd "$tools/.." && pwd)
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
peer="$build/scripts/bench.d/mesh3_labels_peer"
cmake --build "$build" --target seg2tet meshinfo mesh3_labels_peer > /dev/null
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

# verdict IMG MESH: meshinfo's certificate of MESH's regions against IMG.
verdict() {
  "$tools/meshinfo" "$2" --image "$1" --json > "$work/mi.json" 2> "$work/mi.err" || true
  /usr/bin/python3 - "$work/mi.json" "$work/mi.err" <<'P'
import json, sys
try: c = json.load(open(sys.argv[1]))['certificate']
except Exception: print('no: ' + open(sys.argv[2]).read().strip()[-60:]); sys.exit()
if c['verdict'] == 'ok': print('yes'); sys.exit()
v = c['voxel_centres']
print('no: %s (%s)' % (c['verdict'], 'checks ' + ', '.join(k for k, x in c['checks'].items() if x is False) +
      '; %d of %d voxel centres wrong' % (v['wrong'], v['checked'])))
P
}

printf "  %-6s %-22s %7s %7s %7s %11s %9s %8s %9s  %s\n" map mesher wall_s cpu_s peak_MB tetrahedra min_dihed under_10 max_ratio certified
for m in $maps; do
  case $m in
    brain) img=$src/share/data/brain-kmeans-labels.nii.gz ;;
    head|head2) img=$work/$m.mha; /usr/bin/python3 "$here/labelmap.py" "$m" "$img" "${HEAD_SIZE:-64}" ;;
    *) echo "seg2tet.sh: unknown map $m" >&2; exit 2 ;;
  esac
  t=$(timed "$tools/seg2tet" -q "$img" "$work/$m.msh" --stats "$work/$m.json")
  /usr/bin/python3 - "$work/$m.json" "$m" "$t" "$(verdict "$img" "$work/$m.msh")" <<'P'
import json, sys
s = json.load(open(sys.argv[1])); t = s['tetrahedra']; q = t['quality']
verdict = 'yes' if s['all_certified'] else 'no: ' + s['certificate'].get('failure', '')[:60]
print("  %-6s %-22s %s %11d %9.2f %7.2f%% %9.2f  %s; meshinfo %s" % (sys.argv[2], 'seg2tet', sys.argv[3], t['tetrahedra'],
      q['min_dihedral_degrees'], 100 * q['share_dihedral_under_10'], q['max_radius_edge_ratio'], verdict, sys.argv[4]))
P
  t=$(timed timeout "$limit" "$peer" "$img" "$work/$m-m3.msh" 0.25)
  read -r secs tets dihed share ratio < <(tail -1 "$work/run.out")
  printf "  %-6s %-22s %s %11d %9.2f %7.2f%% %9.2f  %s\n" "$m" "CGAL Mesh_3 (own ${secs%.*} s)" "$t" "$tets" "$dihed" \
    "$(echo "100 * $share" | bc -l)" "$ratio" "meshinfo $(verdict "$img" "$work/$m-m3.msh")"
done
