#!/usr/bin/env bash
# seg2mesh --fast (issue 39) beside VTK's vtkDiscreteFlyingEdges3D
# (python3-vtk9, flying_edges_peer.py) on the same label maps in one run:
# the bundled brain map (6 labels) and two synthetic maps made by
# labelmap.py with fixed seeds: a head (256^3, 6 nested bumpy shells) and a
# whole body (512x512x400, 130 labels: organs, bones, vessels). Per map and
# mesher: wall and CPU seconds, peak memory (and bytes a voxel), triangles;
# ours also whether every label is certified. Both read the image and write
# a binary zlib-compressed .vtp. The issue's bar: at most 3x the peer's time,
# at most its triangles, at most 16 bytes a voxel.
# On a shared machine compare the CPU seconds: wall time grows with the load.
# $1: the build's tool folder. BENCH_MAPS (default "brain head body") picks maps.
set -euo pipefail
tools=${1:?tool folder}
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
maps=${BENCH_MAPS:-brain head body}
if ! /usr/bin/python3 -c 'import vtk' 2> /dev/null; then echo "  python3-vtk9 not installed: no peer"; fi

run() {  # run NAME OUTFILE CMD...: prints "wall cpu peak_kb" of CMD
  local name=$1; shift
  /usr/bin/time -f "%e %U %S %M" -o "$work/time" "$@" > "$work/$name.out" 2> "$work/$name.err" ||
    echo "  ($name exited $?: $(tail -1 "$work/$name.err"))" >&2
  read -r wall user sys mem < "$work/time"
  echo "$wall $(echo "$user + $sys" | bc) $mem"
}
printf "  %-8s %-30s %8s %8s %8s %8s %11s  %s\n" map mesher wall_s cpu_s peak_MB B/voxel triangles certified
for m in $maps; do
  case $m in
    brain) img=$src/share/data/brain-kmeans-labels.nii.gz ;;
    head) img=$work/head.mha; /usr/bin/python3 "$here/labelmap.py" head "$img" ;;
    body) img=$work/body.mha; /usr/bin/python3 "$here/labelmap.py" body "$img" ;;
    *) echo "seg2mesh_fast.sh: unknown map $m" >&2; exit 2 ;;
  esac
  read -r wall cpu mem < <(run ours "$tools/seg2mesh" -q "$img" "$work/$m.vtp" --fast --stats "$work/$m.json")
  read -r tris cert nvox < <(/usr/bin/python3 - "$work/$m.json" <<'P'
import json, sys
s = json.load(open(sys.argv[1]))
g = s["grid"]
print(s["triangles"], s["all_certified"], g[0] * g[1] * g[2])
P
  )
  printf "  %-8s %-30s %8.1f %8.1f %8.0f %8.1f %11d  %s\n" "$m" "seg2mesh --fast" "$wall" "$cpu" \
    "$(echo "$mem / 1024" | bc)" "$(echo "$mem * 1024 / $nvox" | bc -l)" "$tris" "$cert"
  if /usr/bin/python3 -c 'import vtk' 2> /dev/null; then
    read -r wall cpu mem < <(run peer /usr/bin/python3 "$here/flying_edges_peer.py" "$img" "$work/$m-fe.vtp")
    read -r _ labels _ tris _ < "$work/peer.out"
    printf "  %-8s %-30s %8.1f %8.1f %8.0f %8.1f %11d  (%s labels; %s)\n" "$m" "vtkDiscreteFlyingEdges3D" "$wall" "$cpu" \
      "$(echo "$mem / 1024" | bc)" "$(echo "$mem * 1024 / $nvox" | bc -l)" "$tris" "$labels" "$(cut -d' ' -f5- "$work/peer.out")"
  fi
done
