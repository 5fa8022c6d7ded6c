#!/usr/bin/env bash
# wc2implicit / implicit-eval figures: construction time of f for 256^3 and
# 512^3 images (linear time), and the thesis's Table 6.1 (20,000,000 random
# evaluations of f, and of f with its gradient). $1: the tool folder.
set -euo pipefail
bin=${1:?usage: wc2implicit.sh TOOL_FOLDER}
here=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
threads=$(nproc)
field() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d[sys.argv[2]])" "$1" "$2"; }

# A ball of radius 0.35 n with a tunnel of radius 0.12 n along x (genus 1).
make_ball() {
  python3 - "$1" "$2" <<'PY'
import math, sys
n, out = int(sys.argv[1]), sys.argv[2]
c, R, r = (n - 1) / 2.0, 0.35 * n, 0.12 * n
zero = bytes(n)
with open(out, "wb") as f:
    f.write(("NRRD0004\ntype: uint8\ndimension: 3\nsizes: %d %d %d\nspacings: 1 1 1\nencoding: raw\n\n" % (n, n, n)).encode())
    for z in range(n):
        rows = []
        for y in range(n):
            dy, dz = y - c, z - c
            h2 = R * R - dy * dy - dz * dz
            if h2 < 0 or dy * dy + dz * dz < r * r:
                rows.append(zero); continue
            h = math.sqrt(h2)
            a, b = max(0, math.ceil(c - h)), min(n - 1, math.floor(c + h))
            rows.append(bytes(a) + b"\x01" * (b + 1 - a) + bytes(n - 1 - b))
        f.write(b"".join(rows))
PY
}

echo "Wall-clock seconds, and process CPU seconds (all threads) where the machine is shared."
echo "threads: $threads ($(nproc) cores); load: $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-22s %10s %10s %10s %12s %12s %10s\n' image voxels "EDT s" "weights s" "construct s" "constr. cpu" "write s"
for n in 256 512; do
  make_ball "$n" "$work/ball$n.nrrd"
  if [[ -x "$bin/img2wc" ]]; then
    "$bin/img2wc" "$work/ball$n.nrrd" "$work/wc$n.nrrd" -q
  else
    cp "$work/ball$n.nrrd" "$work/wc$n.nrrd"
  fi
  if ! "$bin/wc2implicit" "$work/wc$n.nrrd" "$work/f$n.nrrd" -q --threads "$threads" --stats "$work/s$n.json"; then
    echo "ball $n^3: wc2implicit failed"; continue
  fi
  printf '%-22s %10s %10.3f %10.3f %12.3f %12.3f %10.3f\n' "ball+tunnel $n^3" "$((n * n * n))" \
    "$(field "$work/s$n.json" distance_seconds)" "$(field "$work/s$n.json" weights_seconds)" \
    "$(field "$work/s$n.json" construction_seconds)" "$(field "$work/s$n.json" construction_cpu_seconds)" \
    "$(field "$work/s$n.json" write_seconds)"
  [[ $n == 512 ]] && rm -f "$work/ball$n.nrrd" "$work/wc$n.nrrd" "$work/f$n.nrrd"
done

echo
echo "Table 6.1 (thesis: 2006 PowerBook G4, one core: about 417 s for f, 715 s for grad f)"
printf '%-14s %10s %10s %12s %12s %14s %14s\n' image points "f s" "f cpu s" "f+grad s" "f+grad cpu s" "evals/s (f)"
for img in ball256 bunny; do
  if [[ $img == bunny ]]; then
    [[ -x "$bin/img2wc" ]] || continue
    "$bin/img2wc" "$here/share/data/bunny00-96.nrrd" "$work/bunny-wc.nrrd" -q
    "$bin/wc2implicit" "$work/bunny-wc.nrrd" "$work/f-bunny.nrrd" -q
    f="$work/f-bunny.nrrd"
  else
    f="$work/f256.nrrd"
  fi
  [[ -f $f ]] || continue
  "$bin/implicit-eval" "$f" --random 20000000 --seed 1 --threads "$threads" --stats "$work/e.json" -q
  "$bin/implicit-eval" "$f" --random 20000000 --seed 1 --threads "$threads" --gradient --stats "$work/eg.json" -q
  printf '%-14s %10s %10.3f %12.3f %12.3f %14.3f %14.3g\n' "$img" 20000000 "$(field "$work/e.json" evaluation_seconds)" \
    "$(field "$work/e.json" evaluation_cpu_seconds)" "$(field "$work/eg.json" evaluation_seconds)" \
    "$(field "$work/eg.json" evaluation_cpu_seconds)" "$(field "$work/e.json" evaluations_per_second)"
done
