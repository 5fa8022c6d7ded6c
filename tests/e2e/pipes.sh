#!/usr/bin/env bash
# Pipes and outputs across every tool: --stats - never shares stdout with
# data (exit 2 before any work, stdout empty); meshinfo --json --stats - is
# one JSON object; on exit 1 or 2 no output is left, temporary ones in $TMPDIR
# and beside the target included; on exit 3 the output is there. Messages:
# a missing folder named, no library print, every stderr line "tool: ...".
source "$(dirname "$0")/lib.sh"
DATA2D="$DATA/BinaryImage.png"

# Inputs for every stage: a well-composed 3D box (its f), a planar chain.
inputs() {
python3 - <<'EOF'
n = 8
body = bytes(1 if 2 <= x <= 5 and 2 <= y <= 5 and 2 <= z <= 4 else 0
             for z in range(n) for y in range(n) for x in range(n))
open("box.nrrd", "wb").write(b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 8 8 8\nencoding: raw\n\n" + body)
body = bytearray(6 * 6 * 6)  # two voxels sharing an edge: not well-composed
body[2 + 6 * (2 + 6 * 2)] = body[3 + 6 * (3 + 6 * 2)] = 1
open("critical.nrrd", "wb").write(b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 6 6 6\nencoding: raw\n\n" + body)
EOF
"$BIN/wc2implicit" -q box.nrrd box-f.nrrd || fail "setup: wc2implicit"
"$BIN/img2poly" -q "$DATA2D" s.poly --threshold 128 || fail "setup: img2poly"
"$BIN/poly2tri" -q s.poly s.1.ele || fail "setup: poly2tri"
"$BIN/tri2quad" -q s.1.ele s.q.ele || fail "setup: tri2quad"
echo "0 0 0" > p.txt
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' > tet.off
}
inputs_here() { local d; d=$(dirname "$(shared tet.off inputs)"); cp "$d"/* .; }

# refused TOOL ARGS...: exit 2, nothing on stdout, one stderr line "TOOL: ...".
refused() {
  local tool=$1; shift
  "$BIN/$tool" "$@" > out.bin 2> err.txt; local rc=$?
  [[ $rc -eq 2 ]] || fail "$tool $*: exit $rc, want 2"
  [[ ! -s out.bin ]] || fail "$tool $*: stdout has $(wc -c < out.bin) bytes"
  [[ $(wc -l < err.txt) -eq 1 && $(head -c $((${#tool} + 2)) err.txt) == "$tool: " ]] ||
    fail "$tool $*: stderr: $(cat err.txt)"
}

one_object() {  # KEY=VALUE... < JSON: stdout is one object holding each pair
  python3 -c '
import json, sys
d = json.loads(sys.stdin.read())
for kv in sys.argv[1:]:
    k, v = kv.split("=", 1)
    assert str(d[k]) == v, (k, d[k], v)
' "$@"
}

# OUT - with --stats -.
case_stats_dash_refused_when_data_is_on_stdout() {
  inputs_here
refused img2wc "$DATA/bunny00-96.nrrd" - --stats -
refused wc2implicit box.nrrd - --stats -
refused img2poly "$DATA2D" - --threshold 128 --stats -
refused poly2tri s.poly - --stats -
refused tri2quad s.1.ele - --stats -
refused quadsmooth s.q.ele - --stats -
refused implicit-eval box-f.nrrd p.txt --stats -            # values on stdout by default
refused implicit-eval box-f.nrrd p.txt -o - --stats -
refused meshinfo tet.off --stats -                           # the text report is on stdout
refused implicit2mesh box-f.nrrd - --stats -
refused seg2mesh box.nrrd - --stats -
# The check comes before the work: a missing input is not even opened.
refused img2wc no-such-input.nrrd - --stats -
}

# Runs that write no data to stdout keep --stats -: one JSON object there.
case_stats_dash_one_object_when_stdout_is_free() {
  inputs_here
"$BIN/implicit-eval" box-f.nrrd --random 100 --stats - -q > r.json || fail "implicit-eval --random --stats -: exit $?"
one_object tool=implicit-eval exit_status=0 < r.json || fail "implicit-eval --random --stats -: $(cat r.json)"
"$BIN/img2wc" box.nrrd b.nrrd --stats - -q > w.json || fail "img2wc OUT --stats -: exit $?"
one_object tool=img2wc exit_status=0 < w.json || fail "img2wc FILE --stats -: $(cat w.json)"

# meshinfo --json --stats -: one object, the report's keys first, then the run's.
"$BIN/meshinfo" --json tet.off --stats - > m.json || fail "meshinfo --json --stats -: exit $?"
one_object tool=meshinfo exit_status=0 components=1 euler=[2] faces=4 < m.json || fail "meshinfo --json --stats -: $(cat m.json)"
[[ $(python3 -c 'import json, sys; print(*list(json.load(sys.stdin))[:2])' < m.json) == "components euler" ]] ||
  fail "meshinfo --json --stats -: the report's keys do not come first"
# Its error with --stats -: still one object, naming the error.
"$BIN/meshinfo" --json missing.off --stats - > m.json 2> /dev/null
one_object exit_status=1 < m.json || fail "meshinfo error --stats -: $(cat m.json)"
}

# 2. Exit 1 or 2 leaves nothing: outputs go to the empty folder o/, TMPDIR is
# the empty folder tmp/ (stdin spools, the file behind "-"); both stay empty.
# leaves_nothing WANT STDIN TOOL ARGS...
leaves_nothing() {
  local want=$1 input=$2 tool=$3; shift 3
  rm -rf o tmp; mkdir o tmp
  TMPDIR=$PWD/tmp "$BIN/$tool" "$@" < "$input" > out.bin 2> err.txt; local rc=$?
  [[ $rc -eq $want ]] || fail "$tool $*: exit $rc, want $want ($(cat err.txt))"
  [[ -z $(ls -A o) ]] || fail "$tool $*: left in the output folder: $(ls -A o)"
  [[ -z $(ls -A tmp) ]] || fail "$tool $*: left in TMPDIR: $(ls -A tmp)"
  [[ ! -s out.bin ]] || fail "$tool $*: stdout has $(wc -c < out.bin) bytes"
}
case_exit_1_2_leave_nothing() {
  inputs_here
printf '0 0 0\n0.5 0.5 0.5\n100 100 100\n' > p3.txt   # the last point outside the domain
leaves_nothing 1 box.nrrd img2wc - o/w.nrrd --label 9
leaves_nothing 1 box.nrrd img2wc - - --label 9
leaves_nothing 2 box.nrrd img2wc - o/w.xyz
leaves_nothing 1 critical.nrrd wc2implicit - o/f.nrrd
leaves_nothing 1 critical.nrrd wc2implicit - -
leaves_nothing 1 p3.txt implicit-eval box-f.nrrd - -o o/v.txt     # written up to line 3
leaves_nothing 1 p3.txt implicit-eval box-f.nrrd -                 # the same behind "-"
leaves_nothing 1 box.nrrd implicit2mesh - o/m.off                   # not an implicit function file
leaves_nothing 2 /dev/null implicit2mesh box-f.nrrd o/m.off --ratio 1
leaves_nothing 1 box.nrrd seg2mesh - o/m.vtp --labels 9
leaves_nothing 2 box.nrrd seg2mesh - o/m.msh --msh-version 3
leaves_nothing 1 "$DATA2D" img2poly - o/s.poly --threshold 128 --svg o/nodir/s.svg  # OUT done, --svg fails
leaves_nothing 1 /dev/null poly2tri s.poly o/m.1.ele --svg o/nodir/m.svg    # .ele, .node, .poly done
leaves_nothing 1 /dev/null tri2quad s.1.ele o/q.ele --svg o/nodir/q.svg
leaves_nothing 1 /dev/null tri2quad s.1.ele - --svg o/nodir/q.svg
leaves_nothing 1 /dev/null quadsmooth s.q.ele o/qs.ele --svg o/nodir/qs.svg
leaves_nothing 1 critical.nrrd meshinfo tet.off --image -
}

# Exit 3: the output is written, whole, and nothing else is left.
case_exit_3_leaves_the_whole_output() {
  inputs_here
rm -rf o tmp; mkdir o tmp
TMPDIR=$PWD/tmp "$BIN/poly2tri" -q s.poly o/m.1.ele --max-edge 1 --max-vertices 34000; rc=$?
[[ $rc -eq 3 ]] || fail "poly2tri --max-vertices: exit $rc, want 3"
[[ $(ls -A o | tr '\n' ' ') == "m.1.ele m.1.node m.1.poly " && -z $(ls -A tmp) ]] || fail "poly2tri exit 3 left: $(ls -A o tmp)"
"$BIN/meshinfo" --json o/m.1.ele | one_object components=1 || fail "poly2tri exit 3: the mesh does not read back"
# A small bound holds too (s.1.ele, unbounded, has 619 vertices).
"$BIN/poly2tri" -q s.poly o/b.1.ele --max-vertices 300; rc=$?
nodes=$(grep -v '^#' o/b.1.node | head -1 | cut -d' ' -f1)
[[ $rc -eq 3 && $nodes -le 301 && $(grep -v '^#' s.1.node | head -1 | cut -d' ' -f1) -gt 301 ]] ||
  fail "poly2tri --max-vertices 300: exit $rc, $nodes vertices"
rm -rf o; mkdir o
TMPDIR=$PWD/tmp "$BIN/implicit2mesh" -q box-f.nrrd o/m.off --max-points 10; rc=$?
[[ $rc -eq 3 ]] || fail "implicit2mesh --max-points: exit $rc, want 3"
[[ $(ls -A o) == m.off && -z $(ls -A tmp) ]] || fail "implicit2mesh exit 3 left: $(ls -A o tmp)"
"$BIN/meshinfo" --json o/m.off > m.json || fail "implicit2mesh exit 3: the mesh does not read back"

# A refinement stopped early need not be a manifold: every format still
# holds all its triangles (OFF, PLY, VTK, msh are our own writers; OBJ, STL
# OpenMesh's layout).
"$BIN/img2wc" -q "$DATA/bunny00-96.nrrd" - | "$BIN/wc2implicit" -q - bunny-f.nrrd || fail "setup: bunny f"
for ext in off ply obj stl vtp vtk msh; do
  rm -rf o; mkdir o
  TMPDIR=$PWD/tmp "$BIN/implicit2mesh" -q bunny-f.nrrd o/b.$ext --max-points 100 --threads 1 --stats o.json; rc=$?
  [[ $rc -eq 3 && $(ls -A o) == b.$ext && -z $(ls -A tmp) ]] || fail "implicit2mesh --max-points 100 .$ext: exit $rc, $(ls -A o tmp)"
  n=$(python3 -c 'import json; print(json.load(open("o.json"))["triangles"])')
  case $ext in
    off) got=$(sed -n 2p o/b.off | cut -d" " -f2) ;;
    ply) got=$(head -c 400 o/b.ply | grep -a "^element face" | cut -d" " -f3) ;;
    obj) got=$(grep -c "^f " o/b.obj) ;;
    stl) got=$(od -An -t u4 -j 80 -N 4 o/b.stl | tr -d " ") ;;
    vtp) got=$(grep -ao 'NumberOfPolys="[0-9]*"' o/b.vtp | tr -dc 0-9) ;;
    vtk) got=$(grep -a "^POLYGONS" o/b.vtk | cut -d" " -f2) ;;
    msh) got=$(sed -n '/^\$Elements/{n;p;q}' o/b.msh | cut -d" " -f2) ;;
  esac
  [[ $got == "$n" && $n -gt 0 ]] || fail "implicit2mesh exit 3 .$ext: $got triangles in the file, $n in --stats"
done
}

# 3. Messages. A missing output folder is named as such, before any work
# (the input does not exist either: the folder is what is reported).
nofolder() {  # TOOL ARGS... (the output in nodir/)
  local tool=$1; shift
  "$BIN/$tool" "$@" > /dev/null 2> err.txt; local rc=$?
  [[ $rc -eq 1 && $(wc -l < err.txt) -eq 1 && $(cat err.txt) == "$tool: nodir/"*": no such folder" ]] || fail "$tool $*: exit $rc, $(cat err.txt)"
}
case_missing_folder_named_before_work() {
  inputs_here
nofolder img2wc missing.nrrd nodir/x.nrrd
nofolder wc2implicit missing.nrrd nodir/x.nrrd
nofolder img2poly missing.png nodir/x.poly
nofolder poly2tri missing.poly nodir/x.1.ele
nofolder tri2quad missing.1.ele nodir/x.q.ele
nofolder quadsmooth missing.q.ele nodir/x.qs.ele
nofolder implicit-eval missing.nrrd p.txt -o nodir/v.txt
nofolder meshinfo missing.off --stats nodir/s.json
nofolder implicit2mesh box-f.nrrd nodir/x.off          # found when writing, same words
nofolder seg2mesh missing.nrrd nodir/x.vtp
ls -A | grep -q imgmesh- && fail "a temporary file left: $(ls -A | grep imgmesh-)"
}

# Library prints do not reach the terminal: OpenMesh's STL log, MetaIO's lines.
case_library_prints_caught() {
  inputs_here
"$BIN/implicit2mesh" -q box-f.nrrd x.stl 2> err.txt || fail "implicit2mesh .stl: exit $?"
[[ ! -s err.txt && -s x.stl ]] || fail "implicit2mesh -q .stl: $(cat err.txt)"
cp "$DATA/RatLungSlice1.mha" nodata.mha                       # its .raw is not beside it
printf 'NDims = 3\nDimSize = 4 4 4\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n' > short.mha
head -c 10 /dev/zero >> short.mha                             # 10 of its 64 voxels
for f in nodata short; do
  "$BIN/img2wc" $f.mha o.nrrd 2> err.txt; rc=$?
  [[ $rc -eq 1 && $(wc -l < err.txt) -eq 1 && $(cat err.txt) == "img2wc: $f.mha: cannot read the image"* ]] ||
    fail "img2wc $f.mha: exit $rc, $(cat err.txt)"
done
grep -q "truncated" err.txt || fail "short.mha read as zeros: $(cat err.txt)"
}

# An absent label: the labels that do occur, as ranges.
case_absent_label_lists_the_labels_present() {
  inputs_here
"$BIN/img2wc" box.nrrd o.nrrd --label 9 2> err.txt
[[ $(cat err.txt) == "img2wc: box.nrrd: label 9 does not occur in the image (labels present: 0-1)" ]] ||
  fail "img2wc --label 9: $(cat err.txt)"
python3 -c '
v = [0, 2, 3, 5, 2, 0]
open("labels.nrrd", "wb").write(b"NRRD0004\ntype: uint8\ndimension: 2\nsizes: 3 2\nencoding: raw\n\n" + bytes(v))'
"$BIN/img2poly" labels.nrrd o.poly --label 4 2> err.txt
[[ $(cat err.txt) == *"label 4 does not occur in the image (labels present: 0 2-3 5)" ]] || fail "img2poly --label 4: $(cat err.txt)"
}

# A grey image without --threshold: said, with the fix; a label image is not.
case_grey_image_without_threshold_warned() {
cp "$DATA/BrainT1Slice.png" .
"$BIN/img2poly" "$DATA/BrainT1Slice.png" g.poly 2> err.txt || fail "img2poly grey: exit $?"
grep -q "^img2poly: .*BrainT1Slice.png: .*--threshold" err.txt || fail "img2poly grey image: no warning: $(cat err.txt)"
"$BIN/img2poly" "$DATA/VentricleModel.png" g.poly 2> err.txt || fail "img2poly labels: exit $?"
grep -q -- "--threshold" err.txt && fail "img2poly label image: warned: $(cat err.txt)"
"$BIN/img2poly" -q "$DATA/BrainT1Slice.png" g.poly --threshold 100 2> err.txt
[[ -s err.txt ]] && fail "img2poly --threshold: $(cat err.txt)"
}

# Binary data is refused on a terminal before the work (the input is not read).
case_binary_refused_on_a_terminal() {
if command -v script > /dev/null; then
  for tool in img2wc wc2implicit; do
    said=$(script -qec "$BIN/$tool missing.nrrd -" /dev/null); rc=$?
    [[ $rc -eq 2 && $said == *"$tool: -: refusing to write binary data to a terminal"* ]] || fail "$tool - on a terminal: exit $rc, $said"
  done
else
  echo "note: no script(1), terminal refusal not tested"
fi
}

# Every stderr line starts with the tool's name, with and without -q, on
# succeeding and failing runs (a library print or a bare message would not).
case_every_stderr_line_starts_with_the_tool() {
  inputs_here
  cp "$DATA/BrainT1Slice.png" . && cp "$DATA/RatLungSlice1.mha" nodata.mha
  python3 -c '
v = [0, 2, 3, 5, 2, 0]
open("labels.nrrd", "wb").write(b"NRRD0004\ntype: uint8\ndimension: 2\nsizes: 3 2\nencoding: raw\n\n" + bytes(v))'
  printf 'NDims = 3\nDimSize = 4 4 4\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n' > short.mha
  head -c 10 /dev/zero >> short.mha
while IFS= read -r line; do
  [[ -z $line || $line == \#* ]] && continue
  read -r -a cmd <<< "$line"
  for q in "" -q; do
    "$BIN/${cmd[0]}" "${cmd[@]:1}" $q < /dev/null > /dev/null 2> err.txt
    bad=$(grep -v "^${cmd[0]}: " err.txt)
    [[ -z $bad ]] || fail "${cmd[*]} $q: stderr line without the tool's name: $bad"
  done
done <<'CMDS'
img2wc box.nrrd w.nrrd -v --progress
img2wc critical.nrrd w.nrrd --check
img2wc nodata.mha w.nrrd
img2wc short.mha w.nrrd
img2wc box.nrrd w.nrrd --label 9
img2wc box.nrrd w.nrrd --mode sideways
img2wc box.nrrd - --stats -
wc2implicit box.nrrd f.nrrd -v --progress
wc2implicit critical.nrrd f.nrrd
wc2implicit box.nrrd f.txt
implicit-eval box-f.nrrd p.txt -o v.txt --gradient
implicit-eval box-f.nrrd p3.txt -o v.txt
implicit-eval box-f.nrrd --random 1000 -v
implicit2mesh box-f.nrrd m.stl -v --progress
implicit2mesh box-f.nrrd m.ply --normals
implicit2mesh box-f.nrrd m.obj --max-points 10
implicit2mesh box.nrrd m.off
implicit2mesh box-f.nrrd nodir/m.off
img2poly labels.nrrd l.poly -v --svg l.svg
img2poly BrainT1Slice.png l.poly
img2poly nodata.mha l.poly
poly2tri s.poly m.1.ele -v --svg m.svg
poly2tri s.poly m.1.ele --max-edge 1 --max-vertices 34000
poly2tri s.poly m.1.ele --max-area 1e-9
tri2quad s.1.ele q.ele -v --svg q.svg
tri2quad s.poly q.ele
quadsmooth s.q.ele qs.ele -v --svg qs.svg
quadsmooth s.1.ele qs.vtk
quadsmooth s.q.ele qs.xyz
meshinfo tet.off -v
meshinfo box.nrrd
meshinfo tet.off --image critical.nrrd
meshinfo --no-such-option
CMDS
}

# Write failures after the work: the output path is an existing folder, a
# later file of a multi-file set (.node, .poly) or the --svg is one, stdout
# is /dev/full. Exit 1, one line (-q), and nothing left: the folder o/ holds only
# the folders made here, TMPDIR (tmp/) stays empty.
# write_fails STDOUT FOLDERS TOOL ARGS...: FOLDERS (comma-separated) made in o/ first.
write_fails() {
  local stdout=$1 dirs=$2 tool=$3; shift 3
  rm -rf o tmp; mkdir o tmp
  local d made=""
  for d in ${dirs//,/ }; do mkdir -p "o/$d"; made+="$d "; done
  TMPDIR=$PWD/tmp "$BIN/$tool" "$@" -q < /dev/null > "$stdout" 2> err.txt; local rc=$?
  [[ $rc -eq 1 ]] || fail "$tool $* (> $stdout): exit $rc, want 1 ($(cat err.txt))"
  [[ $(wc -l < err.txt) -eq 1 && $(grep -c "^$tool: " err.txt) -eq 1 ]] || fail "$tool $* (> $stdout): stderr: $(cat err.txt)"
  [[ "$(ls -A o | tr '\n' ' ')" == "$made" ]] || fail "$tool $* (> $stdout): left in the output folder: $(ls -A o)"
  [[ -z $(ls -A tmp) ]] || fail "$tool $* (> $stdout): left in TMPDIR: $(ls -A tmp)"
}
case_write_failures_leave_nothing() {
  inputs_here
  local n=/dev/null f=/dev/full
  # The output itself an existing folder.
  write_fails $n w.nrrd img2wc box.nrrd o/w.nrrd
  write_fails $n f.nrrd wc2implicit box.nrrd o/f.nrrd
  write_fails $n v.txt implicit-eval box-f.nrrd p.txt -o o/v.txt
  write_fails $n m.off implicit2mesh box-f.nrrd o/m.off --max-points 10
  write_fails $n s.poly img2poly "$DATA2D" o/s.poly --threshold 128
  write_fails $n m.1.ele poly2tri s.poly o/m.1.ele
  write_fails $n q.ele tri2quad s.1.ele o/q.ele
  write_fails $n qs.ele quadsmooth s.q.ele o/qs.ele
  write_fails $n s.json meshinfo tet.off --stats o/s.json
  write_fails $n s.json img2wc box.nrrd o/w.nrrd --stats o/s.json
  # A later file of the set: the ones before it are rolled back.
  write_fails $n m.1.node poly2tri s.poly o/m.1.ele
  write_fails $n m.1.poly poly2tri s.poly o/m.1.ele
  write_fails $n q.node tri2quad s.1.ele o/q.ele
  write_fails $n q.poly tri2quad s.1.ele o/q.ele
  write_fails $n qs.node quadsmooth s.q.ele o/qs.ele
  write_fails $n qs.poly quadsmooth s.q.ele o/qs.ele
  # --svg that cannot be written (a folder; one in no folder is refused before the work).
  write_fails $n x.svg img2poly "$DATA2D" o/s.poly --threshold 128 --svg o/x.svg
  write_fails $n x.svg poly2tri s.poly o/m.1.ele --svg o/x.svg
  write_fails $n x.svg tri2quad s.1.ele o/q.ele --svg o/x.svg
  write_fails $n x.svg tri2quad s.1.ele - --svg o/x.svg
  write_fails $n x.svg quadsmooth s.q.ele o/qs.ele --svg o/x.svg
  # stdout is /dev/full.
  write_fails $f "" img2wc box.nrrd -
  write_fails $f "" wc2implicit box.nrrd -
  write_fails $f "" implicit-eval box-f.nrrd p.txt
  write_fails $f "" implicit2mesh box-f.nrrd - --max-points 10
  write_fails $f "" img2poly "$DATA2D" - --threshold 128
  write_fails $f "" tri2quad s.1.ele -
  write_fails $f "" quadsmooth s.q.ele -
  write_fails $f "" meshinfo tet.off
  write_fails $f "" meshinfo --json tet.off
  write_fails $f "" img2wc box.nrrd o/w.nrrd --stats -
  write_fails $f x.svg img2poly "$DATA2D" - --threshold 128 --svg o/x.svg
}

run_cases "$@"
