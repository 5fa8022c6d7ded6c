#!/usr/bin/env bash
# Conforming multi-label surfaces (issue 40) side by side, one run per map:
# CGAL Mesh_3 on the whole label map (mesh3_labels_peer.cpp: seeded from
# every component of every label, facet angle 30, facet distance 1/4 voxel,
# facet size unbounded), on the map as given and on the map repaired as
# img2wc --labels and the certificate repair it (so that what fails is
# Mesh_3's, not the repair's); seg2mesh --fast; and seg2mesh --conforming
# when its --help lists it. Maps: the bundled brain map and a synthetic head
# (labelmap.py head, fixed seed: nested shells, triple curves, a thin falx)
# of HEAD_SIZE^3 voxels (default 256, as in seg2mesh_fast.sh: Mesh_3 meshes
# it in about 25 s). Per mesher: wall and CPU seconds, peak memory,
# triangles, smallest angle, % of triangles with an angle under 24 degrees,
# and the interface certificate (`meshinfo OUT --image MAP`, against the map
# repaired as seg2mesh --fast repairs it) per label and per interface:
# labels certified, labels meshed of the map's, interfaces certified, K(X)
# patches matched, the repaired map's voxel components (per label, 0
# included) with a triangle of their label, voxel centres on the wrong side,
# the first failure (interface_metrics.py).
# On a shared machine compare the CPU seconds: wall time grows with the load.
#   $1: the build's tool folder. BENCH_MAPS (default "brain head") picks
#   maps; HEAD_SIZE the head's size; MESH3_TIMEOUT (default 1800) the seconds
#   Mesh_3 may take; MESH3_SIZE Mesh_3's facet size bound in voxels (0, the
#   default: none).
set -euo pipefail
tools=${1:?tool folder}
build=$(cd "$tools/.." && pwd)
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
peer="$build/scripts/bench.d/mesh3_labels_peer"
cmake --build "$build" --target seg2mesh meshinfo img2wc mesh3_labels_peer > /dev/null
maps=${BENCH_MAPS:-brain head}
limit=${MESH3_TIMEOUT:-1800}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if ! /usr/bin/python3 -c 'import vtk' 2> /dev/null; then echo "  python3-vtk9 not installed: no metrics" >&2; exit 1; fi
conforming=no
# (grep -q would close the pipe early: seg2mesh's SIGPIPE fails it under pipefail)
grep -- '--conforming' > /dev/null < <("$tools/seg2mesh" --help) && conforming=yes

row() {  # row MAP NAME OUT.vtp IMAGE CMD...: time CMD, certify OUT against IMAGE, print a row
  local map=$1 name=$2 out=$3 image=$4 rc=0
  shift 4
  /usr/bin/time -f "%e %U %S %M" -o "$work/time" "$@" > "$work/run.out" 2> "$work/run.err" || rc=$?
  read -r wall user sys mem < <(tail -1 "$work/time")
  printf "  %-6s %-34s %7.1f %7.1f %7.0f" "$map" "$name" "$wall" "$(echo "$user + $sys" | bc)" "$(echo "$mem / 1024" | bc)"
  if [ ! -s "$out" ]; then
    echo "  no output (exit $rc: $(tail -1 "$work/run.err"))"
    return
  fi
  "$tools/meshinfo" -q "$out" --image "$image" --json > "$out.json" 2> /dev/null || true
  # The peer's last line: Mesh_3's own seconds (no reading, extracting, writing).
  local own
  own=$(tail -1 "$work/run.out" | awk 'NF == 3 { printf " mesh3_s=%.1f", $1 }')
  echo "  $(/usr/bin/python3 "$here/interface_metrics.py" "$out" "$out.json" "$work/$map-wc.mha")$own"
  [ "$rc" -eq 0 ] || echo "         (exit $rc: $(tail -1 "$work/run.err"))"
}

echo "seg2mesh --conforming listed by seg2mesh --help: $conforming; $(nproc) cores"
printf "  %-6s %-34s %7s %7s %7s  %s\n" map mesher wall_s cpu_s peak_MB "figures (interface_metrics.py)"
for m in $maps; do
  case $m in
    brain) img=$src/share/data/brain-kmeans-labels.nii.gz ;;
    head) img=$work/head.mha; /usr/bin/python3 "$here/labelmap.py" head "$img" "${HEAD_SIZE:-256}" ;;
    *) echo "seg2mesh_quality.sh: unknown map $m" >&2; exit 2 ;;
  esac
  "$tools/img2wc" -q "$img" --labels all "$work/$m-wc.mha"
  row "$m" "seg2mesh --fast" "$work/$m-fast.vtp" "$img" "$tools/seg2mesh" -q "$img" "$work/$m-fast.vtp" --fast
  if [ "$conforming" = yes ]; then
    row "$m" "seg2mesh --conforming" "$work/$m-conf.vtp" "$img" "$tools/seg2mesh" -q "$img" "$work/$m-conf.vtp" --conforming
  fi
  row "$m" "CGAL Mesh_3 seeded, the map" "$work/$m-m3.vtp" "$img" \
    timeout "$limit" "$peer" "$img" "$work/$m-m3.vtp" 0.25 "${MESH3_SIZE:-0}"
  row "$m" "CGAL Mesh_3 seeded, repaired map" "$work/$m-m3wc.vtp" "$img" \
    timeout "$limit" "$peer" "$work/$m-wc.mha" "$work/$m-m3wc.vtp" 0.25 "${MESH3_SIZE:-0}"
  # The first failures, in the certificate's words.
  for f in "$work/$m"-*.vtp.json; do
    /usr/bin/python3 - "$f" <<'P'
import json, os, sys
c = json.load(open(sys.argv[1]))["interface_image"]
if c["verdict"] != "ok":
    bad = [str(l["label"]) for l in c["labels"]
           if l["verdict"] != "ok" or l.get("voxel_sides", {}).get("wrong_side", 0) > 0]
    print("    %s: %s; labels not certified: %s" % (os.path.basename(sys.argv[1])[:-9], c["failure"], " ".join(bad)))
P
  done
done
