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

# Per label of a synthetic whole-body map (labelmap.py body, fixed seed;
# LABELMAP_SIZE, default the issue's 500 470 136), through the pipeline
# (img2wc --label L | wc2implicit | implicit2mesh, files between the stages,
# each on all cores): CPU seconds of each stage against the label's voxels
# and its crop (issue 37: a label of under 1,000 voxels under 0.2 s whatever
# the scan's size, its implicit file under 1 MB). Labels of at most
# LABELMAP_MAX_VOXELS (default 100000: not the body and its muscle layer).
# The map as users have it: .nii.gz for the table; a small and a
# 900-voxel label in each of .nii.gz, .gz.nrrd, .nrrd, .mha and .zip.mha;
# and the floor of a compressed scan: zlib inflating the .gz.nrrd's voxels
# alone (into a 64 KiB buffer, as img2wc reads them).
size=${LABELMAP_SIZE:-500 470 136}
echo "synthetic body map ${size// /x} (labelmap.py body), per label through the pipeline:"
m=$work/map
/usr/bin/python3 "$src/scripts/bench.d/labelmap.py" body "$m.nii.gz,$m.gz.nrrd,$m.nrrd,$m.mha,$m.zip.mha" $size
cpu_of() {  # cpu_of CMD...: CPU seconds (user + system) and peak kB of CMD
  /usr/bin/time -f "%U %S %M" -o "$work/t" "$@" > /dev/null 2>&1 || echo "  ($* exited $?)" >&2
  read -r u s k < "$work/t"
  echo "$(echo "$u + $s" | bc) $k"
}
pipeline() {  # pipeline IMAGE LABEL: "img2wc wc2implicit implicit2mesh total implicit_bytes crop_voxels triangles"
  read -r a _ < <(cpu_of "$tools/img2wc" -q "$1" --label "$2" "$work/wc.nrrd" --stats "$work/wc.json")
  read -r b _ < <(cpu_of "$tools/wc2implicit" -q "$work/wc.nrrd" "$work/f.nrrd")
  read -r c _ < <(cpu_of "$tools/implicit2mesh" -q "$work/f.nrrd" "$work/m.ply" --stats "$work/m.json")
  /usr/bin/python3 - "$a" "$b" "$c" "$(stat -c %s "$work/f.nrrd")" "$work/f.nrrd" "$work/m.json" <<'P'
import json, sys
a, b, c, fbytes, f, m = sys.argv[1:]
sizes = next(l for l in open(f, 'rb').read(4096).split(b'\n') if l.startswith(b'sizes:')).split()[1:]
n = 1
for s in sizes:
    n *= int(s)
print(a, b, c, '%.2f' % (float(a) + float(b) + float(c)), fbytes, n, json.load(open(m))['triangles'])
P
}
/usr/bin/python3 - "$m.mha" "${LABELMAP_MAX_VOXELS:-100000}" > "$work/labels" <<'P'
import sys
import numpy as np
data = open(sys.argv[1], 'rb').read()
a = np.frombuffer(data[data.index(b'ElementDataFile = LOCAL\n') + 24:], np.uint8)
counts = np.bincount(a, minlength=256)
for l in np.nonzero(counts)[0]:
    if l and counts[l] <= int(sys.argv[2]):
        print(l, counts[l])
P
printf "  %6s %8s %12s %8s %12s %14s %8s %12s %10s\n" label voxels "crop voxels" "img2wc s" "wc2implicit s" "implicit2mesh s" "total s" "implicit B" triangles
sort -k2,2n "$work/labels" > "$work/sorted"
while read -r L n; do
  read -r a b c t fb cv tri < <(pipeline "$m.nii.gz" "$L")
  printf "  %6d %8d %12d %8.2f %12.2f %14.2f %8.2f %12d %10d\n" "$L" "$n" "$cv" "$a" "$b" "$c" "$t" "$fb" "$tri"
  echo "$n $t $fb" >> "$work/per_label"
done < "$work/sorted"
/usr/bin/python3 - "$work/per_label" <<'P'
import statistics, sys
rows = [tuple(map(float, l.split())) for l in open(sys.argv[1])]
small = [r for r in rows if r[0] < 1000]
if small:
    print('  labels under 1,000 voxels: %d; total CPU s median %.2f, max %.2f (bar 0.2); implicit file max %d B (bar 1 MB)' % (
        len(small), statistics.median(r[1] for r in small), max(r[1] for r in small), max(r[2] for r in small)))
P
small=$(head -1 "$work/sorted" | cut -d' ' -f1)
near900=$(awk '$2 < 1000 { l = $1 } END { print l }' "$work/sorted")
echo "  by format (CPU s: img2wc / the pipeline's total):"
for f in nii.gz gz.nrrd nrrd mha zip.mha; do
  line="    .$f"
  for L in $small $near900; do
    read -r a b c t _ < <(pipeline "$m.$f" "$L")
    line+=$(printf "   label %d: %.2f / %.2f" "$L" "$a" "$t")
  done
  echo "$line"
done
cat > "$work/inflate.c" <<'C'
/* inflate FILE: inflate the gzip stream after FILE's NRRD header into a 64 KiB buffer reused; prints the bytes. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>
int main(int argc, char** argv) {
  FILE* f = fopen(argv[1], "rb");
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  rewind(f);
  unsigned char* in = malloc(n);
  if (fread(in, 1, n, f) != (size_t)n) return 1;
  unsigned char* at = (unsigned char*)strstr((char*)in, "\n\n") + 2;
  z_stream z = {0};
  inflateInit2(&z, 32 + MAX_WBITS);
  z.next_in = at;
  z.avail_in = (uInt)(in + n - at);
  static unsigned char out[65536];
  size_t total = 0;
  int rc;
  do {
    z.next_out = out;
    z.avail_out = sizeof out;
    rc = inflate(&z, Z_NO_FLUSH);
    total += sizeof out - z.avail_out;
  } while (rc == Z_OK);
  printf("%zu\n", total);
  return rc != Z_STREAM_END;
}
C
"${CC:-cc}" -O2 -o "$work/inflate" "$work/inflate.c" -lz
read -r floor _ < <(cpu_of "$work/inflate" "$m.gz.nrrd")
printf "  floor: zlib inflating the .gz.nrrd's %d voxels alone: %.2f CPU s\n" "$(echo $size | awk '{ print $1 * $2 * $3 }')" "$floor"
