#!/usr/bin/env bash
# seg2mesh: every label of the bundled brain segmentation (labels 1-6) in one
# run, beside the same labels (those seg2mesh meshed, read from its --stats)
# one after the other through the pipeline
# (img2wc --label L | wc2implicit | implicit2mesh, each stage on all cores),
# at --roughness 90 (degrees; the default before 2026-12-03 was 90, now 120:
# kept at 90 so the figures compare with the earlier runs). Wall time,
# CPU time, peak memory, triangles, and whether every label is certified.
# On a shared machine compare the CPU seconds too: the wall time of either
# run grows with the other processes' load.
# $1: the build's tool folder; JOBS (default: the core count) for seg2mesh.
set -euo pipefail
tools=${1:?tool folder}
src=$(cd "$(dirname "$0")/../.." && pwd)
data="$src/share/data/brain-kmeans-labels.nii.gz"
jobs=${JOBS:-$(nproc)}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
G=90

echo "brain-kmeans-labels.nii.gz, every label, --roughness $G, $(nproc) cores:"
ok=yes
/usr/bin/time -f "%e %U %S %M" -o "$work/time" \
  "$tools/seg2mesh" -q "$data" "$work/all.ply" --roughness $G --jobs "$jobs" --stats "$work/all.json" || ok=no
read -r wall user sys mem < "$work/time"
triangles=$(grep -o '"triangles": [0-9]*' "$work/all.json" | head -1 | awk '{print $2}')
printf "  %-44s %8.1f s wall %10d triangles   all certified: %s   (%.0f CPU s, %.0f MB)\n" \
  "seg2mesh --jobs $jobs" "$wall" "$triangles" "$ok" "$(echo "$user + $sys" | bc)" "$(echo "$mem / 1024" | bc)"
labels=$(python3 -c 'import json, sys; print(*(l["label"] for l in json.load(open(sys.argv[1]))["labels"]))' "$work/all.json")
echo "  labels: $labels"
# Per label: its voxels, the crop it was meshed on (its box plus the margin),
# its seconds (a label costs its crop, not the scan).
python3 - "$work/all.json" <<'P'
import json, sys
print("  %6s %10s %14s %10s %10s" % ("label", "voxels", "crop voxels", "triangles", "seconds"))
for l in json.load(open(sys.argv[1]))["labels"]:
    c = l.get("crop_size", [0, 0, 0])
    print("  %6d %10d %14d %10d %10.2f" % (l["label"], l["voxels"], c[0] * c[1] * c[2], l["triangles"], l["seconds"]))
P
start=$(date +%s.%N)
ok=yes
triangles=0
T() { /usr/bin/time -f "%U %S" -a -o "$work/cpu" "$@"; }
for L in $labels; do
  T "$tools/img2wc" -q "$data" --label $L "$work/wc$L.nrrd"
  T "$tools/wc2implicit" -q "$work/wc$L.nrrd" "$work/f$L.nrrd"
  T "$tools/implicit2mesh" -q "$work/f$L.nrrd" "$work/l$L.ply" --roughness $G --stats "$work/s$L.json" || ok=no
  triangles=$((triangles + $(grep -o '"triangles": [0-9]*' "$work/s$L.json" | head -1 | awk '{print $2}')))
done
seq=$(echo "$(date +%s.%N) - $start" | bc)
cpu=$(awk '{ s += $1 + $2 } END { print s }' "$work/cpu")
printf "  %-44s %8.1f s wall %10d triangles   all certified: %s   (%.0f CPU s)\n" "one label after the other (pipeline)" \
  "$seq" "$triangles" "$ok" "$cpu"

printf "  speed-up %.2f\n" "$(echo "$seq / $wall" | bc -l)"
