#!/usr/bin/env bash
# img2wc: time and peak memory of the repair on 256^3 and 512^3 volumes with
# scattered critical configurations, next to a plain pass over an already
# well-composed volume of the same size (the issue's bar: at most +50%);
# then |P|/(C1+C2) on the real brain segmentation in share/data.
# $1: the tool folder.
set -euo pipefail
BIN=${1:?usage: img2wc.sh TOOL_DIR}
W="$BIN/img2wc"
work=$(mktemp -d "${TMPDIR:-/tmp}/img2wc-bench.XXXXXX")
trap 'rm -rf "$work"' EXIT

# gen N SCATTER OUT: a solid box (inset N/8) in a background margin; with
# SCATTER, one voxel pair of the other colour on every lattice site (step 8)
# with probability 1/2: edge-diagonal pairs (C1) or corner pairs (C2),
# outside and inside the box.
gen() {
  python3 - "$@" <<'PY'
import random, sys
n, scatter, out = int(sys.argv[1]), sys.argv[2] == '1', sys.argv[3]
a = bytearray(n * n * n)
lo, hi = n // 8, n - n // 8
row = b'\x01' * (hi - lo)
for z in range(lo, hi):
    for y in range(lo, hi):
        o = lo + n * (y + n * z)
        a[o:o + hi - lo] = row
if scatter:
    rnd = random.Random(1)
    for z in range(4, n - 8, 8):
        for y in range(4, n - 8, 8):
            for x in range(4, n - 8, 8):
                if rnd.random() < 0.5: continue
                i = x + n * (y + n * z)
                d = 1 + n + (n * n if rnd.random() < 0.3 else 0)  # C1 or C2 partner
                a[i] ^= 1; a[i + d] ^= 1
with open(out, 'wb') as f:
    f.write(b'NRRD0004\ntype: uint8\ndimension: 3\nsizes: %d %d %d\nencoding: raw\n\n' % (n, n, n))
    f.write(a)
PY
}

# CPU time (user + system) is the fair measure on a shared machine; wall
# time is printed too.
run() {  # label input: prints seconds, peak MiB, and the Table 5.1 figures
  /usr/bin/time -f '%e %U %S %M' -o "$work/time" "$W" "$2" "$work/out.nrrd" -q --stats "$work/stats.json"
  read -r wall user sys kib <"$work/time"
  python3 - "$1" "$wall" "$user" "$sys" "$kib" "$work/stats.json" "$work/last" <<'PY'
import json, sys
label, wall, user, sysc, kib, stats, last = sys.argv[1:]
d = json.load(open(stats))
m = d['c1'] + d['c2']
cpu = float(user) + float(sysc)
print('  %-26s cpu %6.2f s  wall %6.2f s  peak %5.0f MiB  C1 %6d  C2 %6d  |P| %6d  |P|/(C1+C2) %s  created %d' % (
    label, cpu, float(wall), int(kib) / 1024, d['c1'], d['c2'], d['changed'],
    '%.3f' % (d['changed'] / m) if m else '-', d['created']))
open(last, 'w').write('%f\n' % cpu)
PY
}

for n in 256 512; do
  echo "img2wc ${n}^3 ($(( n * n * n / 1048576 )) Mi voxels):"
  gen $n 0 "$work/plain.nrrd"
  gen $n 1 "$work/scattered.nrrd"
  run "well-composed (plain pass)" "$work/plain.nrrd"; plain=$(cat "$work/last")
  run "scattered configurations" "$work/scattered.nrrd"; repair=$(cat "$work/last")
  python3 -c "import sys; p, r = float(sys.argv[1]), float(sys.argv[2]); print('  repair / plain pass (cpu): %.2f (bar: <= 1.50)' % (r / p))" "$plain" "$repair"
  rm -f "$work"/*.nrrd
done

data=$(dirname "$0")/../../share/data/brain-kmeans-labels.nii.gz
if [[ -f "$data" ]]; then
  echo "img2wc on a real brain segmentation (ITK's KmeansTest, 128x128x62, labels 1-5):"
  for l in 1 2 3 4 5; do
    for rules in "" --thesis-rules; do
      "$W" "$data" --label $l "$work/k.nrrd" -q $rules --stats "$work/k.json"
      python3 - "$l" "${rules:-greedy}" "$work/k.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[3])); m = d['c1'] + d['c2']
print('  label %s %-15s C1 %6d  C2 %5d  |P| %6d  |P|/(C1+C2) %.3f  created %d' % (
    sys.argv[1], sys.argv[2], d['c1'], d['c2'], d['changed'], d['changed'] / m, d['created']))
PY
    done
  done
fi
