#!/usr/bin/env bash
# meshinfo end to end: hand-made closed and open surfaces with several
# components (OFF), a planar quad mesh (.ele), --json keys, --image against a
# hand-written well-composed NRRD, the certificate by correspondence on a
# ball and a torus meshed by the real tools (and that mesh mirrored), and bad input.
source "$(dirname "$0")/lib.sh"
M="$BIN/meshinfo"
# First line of a compact JSON value: "components" and "euler" are the first keys.
comps() { "$M" --json "$1" | tr -d ' \n' | sed -n 's/^{"components":\([0-9]*\),"euler":\[\([-0-9,]*\)\].*/\1 \2/p'; }

# A cube (a sphere, euler 2) as OFF quads, outward; two cubes and an open
# box (cube without its top: a disk, euler 1); a torus of 6 x 4 quads.
surfaces() {
cat > cube.off <<'O'
OFF
8 6 0
0 0 0
1 0 0
0 1 0
1 1 0
0 0 1
1 0 1
0 1 1
1 1 1
4 0 2 3 1
4 4 5 7 6
4 0 1 5 4
4 2 6 7 3
4 0 4 6 2
4 1 3 7 5
O
{
  echo OFF; echo "24 17 0"
  for s in 0 3 6; do sed -n '3,10p' cube.off | awk -v s=$s '{ print $1 + s, $2, $3 }'; done
  for s in 0 8; do sed -n '11,16p' cube.off | awk -v s=$s '{ print $1, $2 + s, $3 + s, $4 + s, $5 + s }'; done
  sed -n '11,16p' cube.off | grep -v '^4 4 5 7 6$' | awk '{ print $1, $2 + 16, $3 + 16, $4 + 16, $5 + 16 }'
} > three.off
awk 'BEGIN { n = 6; m = 4; print "OFF"; print n * m, n * m, 0
  for (j = 0; j < m; j++) for (i = 0; i < n; i++) {
    u = 2 * 3.14159265 * i / n; v = 2 * 3.14159265 * j / m
    printf "%.6f %.6f %.6f\n", (3 + cos(v)) * cos(u), (3 + cos(v)) * sin(u), sin(v) }
  for (j = 0; j < m; j++) for (i = 0; i < n; i++)
    print 4, j * n + i, j * n + (i + 1) % n, ((j + 1) % m) * n + (i + 1) % n, ((j + 1) % m) * n + i }' > torus.off
}

case_components_euler_boundary_loops() {
  surfaces
[ "$(comps cube.off)" = "1 2" ] || fail "cube: $(comps cube.off)"
out=$(comps three.off)
[ "$out" = "3 2,2,1" ] || fail "two cubes and an open box: '$out'"
OUT=three.txt expect 0 meshinfo three.off
grep -q "1 boundary loop" three.txt || fail "open box: no boundary loop in the text report"
}

case_torus_genus_1() {
  surfaces
[ "$(comps torus.off)" = "1 0" ] || fail "torus: $(comps torus.off)"
"$M" --json torus.off | grep -q '"genus": 1' || fail "torus genus"
}

case_off_on_stdin_is_the_file() {
  surfaces
[ "$("$M" --json - < cube.off | tr -d ' \n' | grep -c '^{"components":1,"euler":\[2\],')" = 1 ] || fail "stdin"
  expect 0 meshinfo --json cube.off
  mv out.txt file.json
  IN=cube.off expect 0 meshinfo --json -
  cmp -s out.txt file.json || fail "- differs from the file"
}

case_planar_quad_strip() {
printf '6 2 0 0\n0 0 0\n1 1 0\n2 2 0\n3 0 1\n4 1 1\n5 2 1\n' > strip.node
printf '2 4 0\n0 0 1 4 3\n1 1 2 5 4\n' > strip.ele
[ "$(comps strip.ele)" = "1 1" ] || fail "strip: $(comps strip.ele)"
"$M" --json strip.ele | grep -q '"non_convex": 0' || fail "strip quads convex"
"$M" --json strip.ele | sed -n 's/.*"min_mu": *\([0-9.e+-]*\).*/\1/p' | awk '{ exit !($1 > 44.999 && $1 <= 45) }' \
  || fail "strip: squares have mu 45"
}

# --image: one voxel in a 4^3 NRRD (well-composed); the cube matches it,
# three.off does not (exit 3).
case_image_one_voxel_matches_the_cube_only() {
  surfaces
{ printf 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n\n'
  for i in $(seq 0 63); do if [ $i = 21 ]; then printf '\001'; else printf '\000'; fi; done; } > voxel.nrrd
OUT=img.txt expect 0 meshinfo cube.off --image voxel.nrrd
grep -q "MATCHES" img.txt || fail "no match line"
expect 3 meshinfo three.off --image voxel.nrrd --json
mv out.txt three-file.json
IN=three.off expect 3 meshinfo - --image voxel.nrrd --json
sed 's/"three.off"/"-"/' three-file.json | cmp -s - out.txt || fail "exit 3: MESH - differs from the file"
# Two voxels sharing only an edge: not well-composed, refused.
{ printf 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n\n'
  for i in $(seq 0 63); do if [ $i = 21 ] || [ $i = 26 ]; then printf '\001'; else printf '\000'; fi; done; } > edge.nrrd
expect 1 meshinfo cube.off --image edge.nrrd
grep -q "well-composed" err.txt || fail "message does not say well-composed"
}

# The certificate by correspondence through the real tools: a ball around
# x = 10 and a solid torus around x = 29 in a 40 x 24 x 24 grid. The mesh
# passes; mirrored in x about the grid's centre (faces flipped, so the
# sphere sits where the torus is) it has the same sorted Euler list and must
# be refused.
case_certificate_ball_torus_through_pipeline_and_mirror() {
python3 - <<'P'
import math
nx, ny, nz = 40, 24, 24
b = bytearray()
for z in range(nz):
    for y in range(ny):
        for x in range(nx):
            ball = (x - 10) ** 2 + (y - 11.5) ** 2 + (z - 11.5) ** 2 <= 36
            torus = (math.hypot(x - 29, y - 11.5) - 6) ** 2 + (z - 11.5) ** 2 <= 2.5 ** 2
            b.append(1 if ball or torus else 0)
open('two.nrrd', 'wb').write(b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 40 24 24\nencoding: raw\n\n" + bytes(b))
P
expect 0 img2wc two.nrrd two-wc.nrrd && expect 0 wc2implicit two-wc.nrrd two-f.nrrd &&
  expect 0 implicit2mesh two-f.nrrd two.off || return
OUT=two.json expect 0 meshinfo --json two.off --image two-wc.nrrd || fail "the right mesh of a ball and a torus"
[ "$(comps two.off)" = "2 0,2" ] || fail "two.off: $(comps two.off)"
[ "$(tr -d ' \n' < two.json | grep -o '"verdict":"ok"' | wc -l)" = 4 ] || fail "two.off: not 4 ok verdicts"
python3 - two.off two-wc.nrrd > swapped.off <<'P'
import re, sys
# Mirror an OFF mesh in x about the centre of an axis-aligned NRRD grid; flip faces.
head = open(sys.argv[2], 'rb').read().split(b'\n\n', 1)[0].decode()
n = int(re.search(r'sizes: *(\d+)', head).group(1))
o = float(re.search(r'space origin: *\(([^,]*),', head).group(1))
s = float(re.search(r'space directions: *\(([^,]*),', head).group(1))
c = o + s * (n - 1) / 2
lines = open(sys.argv[1]).read().split('\n')
nv, nf = map(int, lines[1].split()[:2])
out = lines[:2]
out += [' '.join([repr(2 * c - float(l.split()[0]))] + l.split()[1:]) for l in lines[2:2 + nv]]
out += [' '.join([l.split()[0]] + l.split()[1:][::-1]) for l in lines[2 + nv:2 + nv + nf]]
print('\n'.join(out))
P
[ "$(comps swapped.off)" = "2 0,2" ] || fail "swapped.off: $(comps swapped.off)"
OUT=swapped.txt expect 3 meshinfo swapped.off --image two-wc.nrrd || fail "the swapped mesh"
cp err.txt swapped.err
grep -q "DOES NOT MATCH" swapped.txt || fail "swapped: no mismatch line"
grep -q "euler differs" swapped.txt || fail "swapped: no per-component verdict"
grep -q "mesh component .: euler 2, its bdCA(X) component . has 0" swapped.err || fail "swapped: message $(cat swapped.err)"
}

case_bad_input_exit_1_2() {
  surfaces
head -c 40 cube.off > trunc.off
expect 1 meshinfo trunc.off || fail "truncated OFF"
[ "$(wc -l < err.txt)" = 1 ] || fail "error is not one line"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n' > nan.off
expect 1 meshinfo nan.off || fail "NaN accepted"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n' > id.off
expect 1 meshinfo id.off || fail "bad id accepted"
printf 'OFF\n999999999 999999999 0\n' > huge.off
expect 1 meshinfo huge.off || fail "huge counts accepted"
expect 1 meshinfo nothere.off || fail "missing file"
cp cube.off cube.xyz
expect 1 meshinfo cube.xyz || fail "unknown format"
"$M" 2> /dev/null; [ $? = 2 ] || fail "no argument"
expect 2 meshinfo cube.off --bogus || fail "unknown option"
}

run_cases "$@"
