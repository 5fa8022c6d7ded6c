#!/usr/bin/env bash
# Malformed inputs, every tool: empty and truncated files, corrupt
# compression, NaN and infinity, zero and four dimensions, missing data
# files, out-of-range indices, wrong element kinds. Each must be refused
# within seconds with exit 1, one stderr line "TOOL: FILE: ..." saying what
# is wrong, and no output file. The files are made here, small and fixed.
# (Headers that declare too much data: limits.sh.)
set -u
mkdir -p "$TMP"
cd "$TMP" || exit 1
fail=0
t() { echo "FAIL: $*"; fail=1; }

# refused TOOL PATTERN FILE [ARG...]: the tool's last argument is the output
# (o.* here), if it takes one; FILE is the one the message must name.
refused() {
  local tool=$1 pattern=$2 file=$3
  shift 3
  rm -f o.* err
  local start=$SECONDS
  timeout 20 "$BIN/$tool" "$@" 2>err </dev/null >/dev/null
  local rc=$? took=$((SECONDS - start))
  local what="$tool $* (${file})"
  [[ $rc == 1 ]] || t "$what: exit $rc, expected 1: $(head -c 300 err)"
  [[ $(wc -l <err) == 1 ]] || t "$what: $(wc -l <err) lines on stderr, expected 1: $(head -c 300 err)"
  grep -q "^$tool: $file: .*$pattern" err || t "$what: message '$(head -c 300 err)' does not match '$tool: $file: ...$pattern'"
  ((took <= 10)) || t "$what: took $took s"
  compgen -G 'o.*' >/dev/null && t "$what: left $(echo o.*)"
  return 0
}

# --- images: img2wc, wc2implicit (3D) and img2poly (2D) -----------------------
nrrd_header() {  # TYPE SIZES ENCODING [EXTRA LINE]
  printf 'NRRD0004\ntype: %s\ndimension: %s\nsizes: %s\nencoding: %s\n' "$1" "$(wc -w <<<"$2")" "$2" "$3"
  [[ -z "${4:-}" ]] || printf '%s\n' "$4"
  printf '\n'
}
: >empty.nrrd
{ nrrd_header float "2 2 2" ascii; echo "1 2 nan 4 5 6 7 8"; } >nan.nrrd
{ nrrd_header float "2 2 2" ascii; echo "1 2 inf 4 -5 6 7 8"; } >inf.nrrd
{ nrrd_header uint8 "0 2 2" raw; } >zero.nrrd
{ nrrd_header uint8 "2 2 2 2" raw; printf '0123456789abcdef'; } >four.nrrd
nrrd_header uint8 "4 4 4" raw "data file: absent.raw" >missing.nhdr
printf 'ObjectType = Image\nNDims = 3\nDimSize = 4 4 4\nElementType = MET_UCHAR\nElementDataFile = absent.raw\n' >missing.mhd
head -c 4096 /dev/zero | gzip -9 -c >zeros.gz
{ nrrd_header uint8 "16 16 16" gzip; head -c $(($(stat -c %s zeros.gz) / 2)) zeros.gz; } >truncated-gzip.nrrd
# Flip bytes inside the deflate stream: a corrupt block or a CRC mismatch.
{ nrrd_header uint8 "16 16 16" gzip; head -c 12 zeros.gz; printf '\377\377\377\377'; tail -c +17 zeros.gz; } >corrupt-gzip.nrrd
{ nrrd_header uint8 "10 10 10" raw; head -c 500 /dev/zero; } >truncated.nrrd
for tool in img2wc wc2implicit; do
  refused $tool "not an image ITK can read" empty.nrrd empty.nrrd o.nrrd
  refused $tool "NaN values" nan.nrrd nan.nrrd o.nrrd
  refused $tool "infinite values" inf.nrrd inf.nrrd o.nrrd
  refused $tool "size is zero" zero.nrrd zero.nrrd o.nrrd
  refused $tool "4D image: 2D or 3D expected" four.nrrd four.nrrd o.nrrd
  refused $tool "absent.raw" missing.nhdr missing.nhdr o.nrrd
  refused $tool "cannot read the image" missing.mhd missing.mhd o.nrrd
  refused $tool "expected 4096 bytes but received" truncated-gzip.nrrd truncated-gzip.nrrd o.nrrd
  refused $tool "cannot read the image" corrupt-gzip.nrrd corrupt-gzip.nrrd o.nrrd
  refused $tool "more than the file" truncated.nrrd truncated.nrrd o.nrrd
done
{ nrrd_header uint8 "4 4 4" raw; head -c 64 /dev/zero; } >volume.nrrd
refused img2poly "3D image" volume.nrrd volume.nrrd o.poly
{ nrrd_header float "2 2" ascii; echo "1 nan 0 1"; } >nan2d.nrrd
refused img2poly "NaN values" nan2d.nrrd nan2d.nrrd o.poly
head -c 40 "$DATA/BinaryImage.png" >truncated.png
refused img2poly "cannot read the image" truncated.png truncated.png o.poly

# --- the implicit function file: implicit2mesh and implicit-eval ----------------
{ nrrd_header uint8 "6 6 6" raw; head -c 216 /dev/zero; } >plain.nrrd
{ nrrd_header uint8 "6 6 6" ascii; for z in 0 1 2 3 4 5; do for y in 0 1 2 3 4 5; do for x in 0 1 2 3 4 5; do
  ((x > 0 && x < 5 && y > 0 && y < 5 && z > 0 && z < 5)) && printf '1 ' || printf '0 '; done; done; done; echo; } >cube.nrrd
"$BIN/wc2implicit" -q cube.nrrd f.nrrd || t "wc2implicit on a cube failed"
head -c $(($(stat -c %s f.nrrd) / 2)) f.nrrd >truncated-f.nrrd
sed 's/^imgmesh_d:=.*/imgmesh_d:=nan nan nan/' f.nrrd >nan-d.nrrd
sed 's/^imgmesh_version:=.*/imgmesh_version:=99/' f.nrrd >version.nrrd
for tool in implicit2mesh implicit-eval; do
  out=o.off
  [[ $tool == implicit-eval ]] && out=
  refused $tool "not an image ITK can read" empty.nrrd empty.nrrd $out
  refused $tool "not an implicit function file" plain.nrrd plain.nrrd $out
  refused $tool "cannot read the image" truncated-f.nrrd truncated-f.nrrd $out
  refused $tool "imgmesh_d" nan-d.nrrd nan-d.nrrd $out
  refused $tool "version" version.nrrd version.nrrd $out
done

# --- planar meshes: poly2tri (PSLG), tri2quad, quadsmooth, meshinfo -------------
: >empty.off
printf '3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n' >tri.node
printf '1 3 0\n1 1 2 7\n' >tri.ele                        # vertex 7 does not exist
printf '3 2 0 0\n1 0 0\n2 nan 0\n3 0 1\n' >nan.node
printf '1 3 0\n1 1 2 3\n' >nan.ele
cp tri.node short.node
printf '1 3 0\n1 1 2\n' >short.ele                        # a triangle with two corners
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n' >range.off
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n' >nan.off
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n' >truncated.off
printf 'OFF\n5 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 1.5 0\n5 0 1 2 4 3\n' >pentagon.off
printf '4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n2 0\n1 1 9\n2 2 3\n0\n' >range.poly
printf '4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n' >alone.node
for tool in poly2tri tri2quad quadsmooth; do
  out=o.off
  [[ $tool == poly2tri ]] && out=o.ele
  refused $tool "not an OFF file" empty.off empty.off $out
  refused $tool "vertex 5 does not exist" range.off range.off $out
  refused $tool "'nan' is not a finite number" nan.off nan.off $out
  refused $tool "truncated" truncated.off truncated.off $out
done
refused poly2tri "vertex 9 does not exist" range.poly range.poly o.ele
refused poly2tri "no alone.poly beside it" alone.node alone.node o.ele
refused poly2tri "unknown PSLG format '.ele'" tri.ele tri.ele o.ele
for tool in tri2quad quadsmooth meshinfo; do
  out=o.off
  [[ $tool == meshinfo ]] && out=
  refused $tool "vertex 7 does not exist" tri.ele tri.ele $out
  refused $tool "'nan' is not a finite number" nan.node nan.ele $out
  refused $tool "an element needs 4 fields, has 3" short.ele short.ele $out
done
printf 'OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n' >quad.off
refused tri2quad "element 0 is not a triangle" quad.off quad.off o.off
refused tri2quad "faces must have 3 or 4 vertices" pentagon.off pentagon.off o.off
refused quadsmooth "faces must have 3 or 4 vertices" pentagon.off pentagon.off o.off

# --- surface meshes: meshinfo ----------------------------------------------------
refused meshinfo "not an OFF file" empty.off empty.off
refused meshinfo "bad vertex id '5'" range.off range.off
refused meshinfo "bad vertex coordinate 'nan'" nan.off nan.off
refused meshinfo "truncated" truncated.off truncated.off
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n' >truncated.ply
refused meshinfo "cannot read the mesh" truncated.ply truncated.ply
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n' >range.obj
refused meshinfo "bad vertex reference .4." range.obj range.obj
printf 'solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n' >truncated.stl
refused meshinfo "no faces" truncated.stl truncated.stl
head -c 90 /dev/zero >short-binary.stl
refused meshinfo "no faces" short-binary.stl short-binary.stl

exit $fail
