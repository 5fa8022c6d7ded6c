#!/usr/bin/env bash
# wc2implicit and implicit-eval end to end: analytic values of f at voxel
# centres of a generated anisotropic box image (f = g = signed distance to the
# voxel faces there), domain handling, determinism of --random, bad input,
# and the sample images through img2wc.
set -euo pipefail
mkdir -p "$TMP"
cd "$TMP"
W="$BIN/wc2implicit"
E="$BIN/implicit-eval"
fail() { echo "FAIL: $*" >&2; exit 1; }
# expect CODE CMD...: run CMD, require exit status CODE, keep stderr in err.txt
expect() {
  local want=$1; shift
  set +e; "$@" > out.txt 2> err.txt; local got=$?; set -e
  [[ $got -eq $want ]] || { cat err.txt >&2; fail "exit $got (want $want): $*"; }
}
# near A B TOL: |A - B| <= TOL
near() { awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= t) }'; }

# A box of voxels x 4..15, y 3..14, z 2..13 in a 20x18x16 grid, spacing
# 0.5 0.8 1.2, origin (10, -5, 3): well-composed by construction.
python3 - <<'EOF'
nx, ny, nz = 20, 18, 16
body = bytearray()
for z in range(nz):
    for y in range(ny):
        for x in range(nx):
            body.append(1 if 4 <= x <= 15 and 3 <= y <= 14 and 2 <= z <= 13 else 0)
hdr = ("NRRD0004\ntype: uint8\ndimension: 3\nsizes: %d %d %d\nspace: left-posterior-superior\n"
       "space directions: (0.5,0,0) (0,0.8,0) (0,0,1.2)\nspace origin: (10,-5,3)\nencoding: raw\n\n") % (nx, ny, nz)
open("box.nrrd", "wb").write(hdr.encode() + body)
# Two voxels sharing only an edge: a critical configuration C1.
body = bytearray(6 * 6 * 6)
body[2 + 6 * (2 + 6 * 2)] = 1
body[3 + 6 * (3 + 6 * 2)] = 1
hdr = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 6 6 6\nencoding: raw\n\n"
open("critical.nrrd", "wb").write(hdr.encode() + body)
EOF

expect 0 "$W" box.nrrd box-f.nrrd --stats stats.json
grep -aq "imgmesh_kind:=pu-implicit" box-f.nrrd || fail "no imgmesh_kind field"
grep -aq "imgmesh_version:=1" box-f.nrrd || fail "no imgmesh_version field"
grep -aq "imgmesh_d:=" box-f.nrrd || fail "no imgmesh_d field"
grep -q '"exit_status": 0' stats.json || fail "stats exit_status"
grep -q '"g_min"' stats.json || fail "stats g_min"

# Voxel centres (world = origin + index * spacing) and f = g there:
#  (4,8,7)  foreground, 0.5 voxel from the face x = 3.5:       -0.25
#  (2,8,7)  background, 1.5 voxels from that face:               0.75
#  (9,8,7)  foreground; faces x 3.5/15.5 are 5.5*0.5 = 2.75 away, y 2.5/14.5
#           5.5*0.8 = 4.4, z 1.5/13.5 5.5*1.2 = 6.6:                   -2.75
#  (0,0,0)  background corner: distance to the box corner (4,3,2)-(0.5,0.5,0.5):
#           sqrt((3.5*0.5)^2 + (2.5*0.8)^2 + (1.5*1.2)^2) = sqrt(3.0625 + 4 + 3.24)
printf '12 1.4 11.4\n11 1.4 11.4\n# a comment\n\n14.5, 1.4, 11.4\n10 -5 3\n' > pts.txt
expect 0 "$E" box-f.nrrd pts.txt
mapfile -t vals < out.txt
[[ ${#vals[@]} -eq 4 ]] || fail "want 4 values, got ${#vals[@]}"
near "${vals[0]}" -0.25 1e-6 || fail "f(4,8,7) = ${vals[0]}, want -0.25"
near "${vals[1]}" 0.75 1e-6 || fail "f(2,8,7) = ${vals[1]}, want 0.75"
near "${vals[2]}" -2.75 1e-6 || fail "f(9,8,7) = ${vals[2]}, want -2.75"
near "${vals[3]}" "$(awk 'BEGIN { print sqrt(3.0625 + 4 + 3.24) }')" 1e-6 || fail "f(0,0,0) = ${vals[3]}"

# Gradient: four columns; at the centre of a cell far from the surface f is
# the trilinear interpolant, and between (2,8,7) and (4,8,7) f decreases in x.
printf '11.5 1.4 11.4\n' | "$E" box-f.nrrd - --gradient > grad.txt
read -r f gx gy gz < grad.txt
[[ -n "$gz" ]] || fail "--gradient prints f gx gy gz"
awk -v g="$gx" 'BEGIN { exit !(g < 0) }' || fail "df/dx = $gx should be negative entering the box"

# Outside the domain: an error, or nan with --allow-outside.
printf '9.9 1.4 11.4\n' > outside.txt
expect 1 "$E" box-f.nrrd outside.txt
grep -q "outside the domain" err.txt || fail "outside message"
expect 0 "$E" box-f.nrrd outside.txt --allow-outside
grep -qx "nan" out.txt || fail "--allow-outside prints nan"

# --random: same seed, same checksum, whatever the number of threads.
expect 0 "$E" box-f.nrrd --random 200000 --seed 7 --threads 1 --stats r1.json
expect 0 "$E" box-f.nrrd --random 200000 --seed 7 --threads 2 --stats r2.json
expect 0 "$E" box-f.nrrd --random 200000 --seed 7 --gradient --stats r3.json
c1=$(grep '"checksum"' r1.json)
c2=$(grep '"checksum"' r2.json)
[[ "$c1" == "$c2" ]] || fail "checksum depends on threads: $c1 vs $c2"
grep -q '"evaluations_per_second"' r1.json || fail "no evaluations_per_second"
grep -q '"gradient_checksum"' r3.json || fail "no gradient_checksum"

# The output does not depend on the number of threads.
expect 0 "$W" box.nrrd box-t1.nrrd --threads 1
expect 0 "$W" box.nrrd box-t2.nrrd --threads 2
cmp -s box-t1.nrrd box-t2.nrrd || fail "output depends on --threads"

# NRRD on stdout, stdin input: the same bytes as the file output.
"$W" box.nrrd - -q > piped.nrrd
cmp -s piped.nrrd box-t1.nrrd || fail "OUT - differs from the file output"
cat box.nrrd | "$W" - piped2.nrrd -q
cmp -s piped2.nrrd box-t1.nrrd || fail "IN - differs from the file input"

# Bad input.
expect 1 "$W" critical.nrrd x.nrrd
grep -q "img2wc" err.txt || fail "the not-well-composed message should name img2wc"
[[ ! -e x.nrrd ]] || fail "output written for a refused input"
head -c 200 box.nrrd > truncated.nrrd
expect 1 "$W" truncated.nrrd x.nrrd
expect 1 "$W" "$DATA/BinaryImage.png" x.nrrd
expect 1 "$W" missing.nrrd x.nrrd
expect 2 "$W" box.nrrd x.vtk
expect 2 "$W" box.nrrd
expect 1 "$E" box.nrrd pts.txt
grep -q "pu-implicit" err.txt || fail "a plain image is not an implicit file"
printf '1 2\n' > bad.txt
expect 1 "$E" box-f.nrrd bad.txt
printf '12 1.4 nan\n' > bad.txt
expect 1 "$E" box-f.nrrd bad.txt
head -c 300 box-f.nrrd > truncated-f.nrrd
expect 1 "$E" truncated-f.nrrd pts.txt
expect 2 "$E" box-f.nrrd pts.txt --random 10

# The sample images: not well-composed as they come; through img2wc they are.
expect 1 "$W" "$DATA/bunny00-96.nrrd" x.nrrd
grep -q "img2wc" err.txt || fail "bunny: message should name img2wc"
if [[ -x "$BIN/img2wc" ]]; then
  for name in bunny00-96 elephant-96; do
    "$BIN/img2wc" "$DATA/$name.nrrd" "$name-wc.nrrd" -q
    expect 0 "$W" "$name-wc.nrrd" "$name-f.nrrd" --stats "$name.json"
    # Every voxel centre is at least half a voxel from the voxel faces, and
    # some lie exactly there; d stays within delta/5.
    sp=$(python3 -c "import json; print(json.load(open('$name.json'))['spacing'][0])")
    gmin=$(python3 -c "import json; print(json.load(open('$name.json'))['g_min'])")
    d0=$(python3 -c "import json; print(json.load(open('$name.json'))['d'][0])")
    near "$gmin" "$(awk -v s="$sp" 'BEGIN { print s / 2 }')" "$(awk -v s="$sp" 'BEGIN { print s * 1e-6 }')" ||
      fail "$name: g_min $gmin, want half the spacing $sp"
    awk -v d="$d0" -v s="$sp" 'BEGIN { exit !(d > 0 && d <= s / 5) }' || fail "$name: d $d0 not in (0, delta/5]"
    expect 0 "$E" "$name-f.nrrd" --random 100000 --gradient --stats "$name-r.json"
    # f = g at voxel centres: read g back with a small independent NRRD
    # reader, evaluate f at 200 random centres (world coordinates).
    python3 - "$name-f.nrrd" centres.txt expected.txt <<'PY'
import gzip, random, re, struct, sys
raw = open(sys.argv[1], "rb").read()
end = raw.index(b"\n\n")
hdr = {}
for line in raw[:end].decode().splitlines()[1:]:
    if ":" in line and not line.startswith("#") and ":=" not in line:
        k, v = line.split(":", 1)
        hdr[k.strip()] = v.strip()
assert hdr["type"] == "float" and hdr.get("endian", "little") == "little"
n = [int(x) for x in hdr["sizes"].split()]
body = raw[end + 2:]
if hdr["encoding"] == "gzip":
    body = gzip.decompress(body)
g = struct.unpack("<%df" % (n[0] * n[1] * n[2]), body[: 4 * n[0] * n[1] * n[2]])
vec = lambda s: [float(x) for x in s.strip("()").split(",")]
dirs = [vec(v) for v in re.findall(r"\([^)]*\)", hdr["space directions"])]
org = vec(hdr["space origin"])
rng = random.Random(5)
with open(sys.argv[2], "w") as pts, open(sys.argv[3], "w") as exp:
    for _ in range(200):
        i, j, k = (rng.randrange(m) for m in n)
        w = [org[a] + i * dirs[0][a] + j * dirs[1][a] + k * dirs[2][a] for a in range(3)]
        pts.write("%.17g %.17g %.17g\n" % tuple(w))
        exp.write("%.9g\n" % g[i + n[0] * (j + n[1] * k)])
PY
    expect 0 "$E" "$name-f.nrrd" centres.txt
    paste out.txt expected.txt | awk '{ d = $1 - $2; if (d < 0) d = -d; if (d > 1e-6 || ($1 < 0) != ($2 < 0)) bad++ }
      END { exit bad > 0 }' || fail "$name: f differs from g at a voxel centre"
  done
else
  echo "note: $BIN/img2wc not built; skipping the sample images through img2wc"
fi
echo "wc2implicit e2e: ok"
