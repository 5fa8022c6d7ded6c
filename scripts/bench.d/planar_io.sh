#!/usr/bin/env bash
# Planar text I/O (Triangle's .node/.ele and OFF) on 10^6 quads (the jittered
# 1000 x 1000 grid of quadsmooth.sh): quadsmooth with no pass and no clean-up
# reads the mesh and writes it back: its wall and CPU time are the text I/O
# plus the mesh check, the set-up and the two quality reports (quadsmooth's
# --stats "seconds" is the same run less start-up). Three runs each: the
# machine is shared.
# $1: tool folder.
set -euo pipefail
BIN=${1:?usage: planar_io.sh TOOL_FOLDER}
work=$(mktemp -d "${TMPDIR:-/tmp}/planar-io-bench.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"
stat() { sed -n "s/^ *\"$1\": *\([^,]*\),*$/\1/p" "$2"; }
python3 - <<'PY'
import random
n = 1000; m = n + 1; r = random.Random(1)
with open("big.node", "w") as f:
    f.write("%d 2 0 1\n" % (m * m))
    for j in range(m):
        f.writelines("%d %.10g %.10g %d\n" % ((j * m + i,) + ((i, j) if i in (0, n) or j in (0, n) else
                     (i + r.uniform(-0.25, 0.25), j + r.uniform(-0.25, 0.25))) + (int(i in (0, n) or j in (0, n)),))
                     for i in range(m))
with open("big.ele", "w") as f:
    f.write("%d 4 0\n" % (n * n))
    f.writelines("%d %d %d %d %d\n" % (j * n + i, j * m + i, j * m + i + 1, j * m + i + m + 1, j * m + i + m)
                 for j in range(n) for i in range(n))
PY
"$BIN/quadsmooth" -q --iterations 0 --no-cleanup big.ele big.off
echo "10^6 quads: $(du -m big.node big.ele | awk '{s += $1} END {print s}') MB as .node + .ele, $(du -m big.off | cut -f1) MB as OFF"
for fmt in ele off; do
  for run in 1 2 3; do
    /usr/bin/time -f "%e %U %S" -o time.txt "$BIN/quadsmooth" -q --iterations 0 --no-cleanup --threads 1 \
      big.$fmt out.$fmt --stats s.json
    read -r wall user sys < time.txt
    printf "  .%s in and out, run %d: %.2f s wall, %.2f s CPU (%.2f s in the tool)\n" \
      "$fmt" "$run" "$wall" "$(echo "$user + $sys" | bc)" "$(stat seconds s.json)"
  done
done
