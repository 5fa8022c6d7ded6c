#!/usr/bin/env bash
# Pipes and outputs across every tool: --stats - never shares stdout with
# data (exit 2 before any work, stdout empty); meshinfo --json --stats - is
# one JSON object.
set -u
rm -rf "$TMP"; mkdir -p "$TMP"
cd "$TMP" || exit 1
fail=0
t() { echo "FAIL: $*"; fail=1; }
DATA2D="$DATA/BinaryImage.png"

# Inputs for every stage: a well-composed 3D box (its f), a planar chain.
python3 - <<'EOF'
n = 8
body = bytes(1 if 2 <= x <= 5 and 2 <= y <= 5 and 2 <= z <= 4 else 0
             for z in range(n) for y in range(n) for x in range(n))
open("box.nrrd", "wb").write(b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 8 8 8\nencoding: raw\n\n" + body)
EOF
"$BIN/wc2implicit" -q box.nrrd box-f.nrrd || t "setup: wc2implicit"
"$BIN/img2poly" -q "$DATA2D" s.poly --threshold 128 || t "setup: img2poly"
"$BIN/poly2tri" -q s.poly s.1.ele || t "setup: poly2tri"
"$BIN/tri2quad" -q s.1.ele s.q.ele || t "setup: tri2quad"
echo "0 0 0" > p.txt
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' > tet.off

# refused TOOL ARGS...: exit 2, nothing on stdout, one stderr line "TOOL: ...".
refused() {
  local tool=$1; shift
  "$BIN/$tool" "$@" > out.bin 2> err.txt; local rc=$?
  [[ $rc -eq 2 ]] || t "$tool $*: exit $rc, want 2"
  [[ ! -s out.bin ]] || t "$tool $*: stdout has $(wc -c < out.bin) bytes"
  [[ $(wc -l < err.txt) -eq 1 && $(head -c $((${#tool} + 2)) err.txt) == "$tool: " ]] ||
    t "$tool $*: stderr: $(cat err.txt)"
}

# 1. OUT - with --stats -.
refused img2wc "$DATA/bunny00-96.nrrd" - --stats -
refused wc2implicit box.nrrd - --stats -
refused img2poly "$DATA2D" - --threshold 128 --stats -
refused poly2tri s.poly - --stats -
refused tri2quad s.1.ele - --stats -
refused quadsmooth s.q.ele - --stats -
refused implicit-eval box-f.nrrd p.txt --stats -            # values on stdout by default
refused implicit-eval box-f.nrrd p.txt -o - --stats -
refused meshinfo tet.off --stats -                           # the text report is on stdout
# The check comes before the work: a missing input is not even opened.
refused img2wc no-such-input.nrrd - --stats -

# Runs that write no data to stdout keep --stats -: one JSON object there.
one_object() {  # KEY=VALUE... < JSON: stdout is one object holding each pair
  python3 -c '
import json, sys
d = json.loads(sys.stdin.read())
for kv in sys.argv[1:]:
    k, v = kv.split("=", 1)
    assert str(d[k]) == v, (k, d[k], v)
' "$@"
}
"$BIN/implicit-eval" box-f.nrrd --random 100 --stats - -q > r.json || t "implicit-eval --random --stats -: exit $?"
one_object tool=implicit-eval exit_status=0 < r.json || t "implicit-eval --random --stats -: $(cat r.json)"
"$BIN/img2wc" box.nrrd b.nrrd --stats - -q > w.json || t "img2wc OUT --stats -: exit $?"
one_object tool=img2wc exit_status=0 < w.json || t "img2wc FILE --stats -: $(cat w.json)"

# meshinfo --json --stats -: one object, the report's keys first, then the run's.
"$BIN/meshinfo" --json tet.off --stats - > m.json || t "meshinfo --json --stats -: exit $?"
one_object tool=meshinfo exit_status=0 components=1 euler=[2] faces=4 < m.json || t "meshinfo --json --stats -: $(cat m.json)"
[[ $(python3 -c 'import json, sys; print(*list(json.load(sys.stdin))[:2])' < m.json) == "components euler" ]] ||
  t "meshinfo --json --stats -: the report's keys do not come first"
# Its error with --stats -: still one object, naming the error.
"$BIN/meshinfo" --json missing.off --stats - > m.json 2> /dev/null
one_object exit_status=1 < m.json || t "meshinfo error --stats -: $(cat m.json)"

echo "pipes e2e: $([[ $fail -eq 0 ]] && echo ok || echo FAILED)"
exit $fail
