#!/usr/bin/env bash
# wc2implicit and implicit-eval end to end: analytic values of f at voxel
# centres of a generated anisotropic box image (f = g = signed distance to the
# voxel faces there), domain handling, determinism of --random, stdin and
# stdout against the files, bad input, and the sample images through img2wc
# (f = g at voxel centres, g and d read from the file).
source "$(dirname "$0")/lib.sh"
# near A B TOL: |A - B| <= TOL
near() { python3 -c "import sys; a, b, t = map(float, sys.argv[1:]); sys.exit(not abs(a - b) <= t)" "$1" "$2" "$3"; }

# A box of voxels x 4..15, y 3..14, z 2..13 in a 20x18x16 grid, spacing
# 0.5 0.8 1.2, origin (10, -5, 3): well-composed by construction.
images() {
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
}
input() { local d; d=$(dirname "$(shared box.nrrd images)"); for f in "$@"; do cp "$d/$f" .; done; }
box_f() { cp "$(dirname "$(shared box.nrrd images)")/box.nrrd" . && expect 0 wc2implicit box.nrrd box-f.nrrd; }
input_f() { input box.nrrd; cp "$(shared box-f.nrrd box_f)" .; }

case_box_f_is_the_signed_distance_at_centres() {
  input box.nrrd
  expect 0 wc2implicit box.nrrd box-f.nrrd
grep -aq "imgmesh_kind:=pu-implicit" box-f.nrrd || fail "no imgmesh_kind field"
grep -aq "imgmesh_version:=1" box-f.nrrd || fail "no imgmesh_version field"
grep -aq "imgmesh_d:=" box-f.nrrd || fail "no imgmesh_d field"
# Voxel centres (world = origin + index * spacing) and f = g there:
#  (4,8,7)  foreground, 0.5 voxel from the face x = 3.5:       -0.25
#  (2,8,7)  background, 1.5 voxels from that face:               0.75
#  (9,8,7)  foreground; faces x 3.5/15.5 are 5.5*0.5 = 2.75 away, y 2.5/14.5
#           5.5*0.8 = 4.4, z 1.5/13.5 5.5*1.2 = 6.6:                   -2.75
#  (0,0,0)  background corner: distance to the box corner (4,3,2)-(0.5,0.5,0.5):
#           sqrt((3.5*0.5)^2 + (2.5*0.8)^2 + (1.5*1.2)^2) = sqrt(3.0625 + 4 + 3.24)
printf '12 1.4 11.4\n11 1.4 11.4\n# a comment\n\n14.5, 1.4, 11.4\n10 -5 3\n' > pts.txt
expect 0 implicit-eval box-f.nrrd pts.txt
mapfile -t vals < out.txt
[[ ${#vals[@]} -eq 4 ]] || fail "want 4 values, got ${#vals[@]}"
near "${vals[0]}" -0.25 1e-6 || fail "f(4,8,7) = ${vals[0]}, want -0.25"
near "${vals[1]}" 0.75 1e-6 || fail "f(2,8,7) = ${vals[1]}, want 0.75"
near "${vals[2]}" -2.75 1e-6 || fail "f(9,8,7) = ${vals[2]}, want -2.75"
near "${vals[3]}" "$(python3 -c 'print((3.0625 + 4 + 3.24) ** 0.5)')" 1e-6 || fail "f(0,0,0) = ${vals[3]}"
}

# Gradient: four columns; at the centre of a cell far from the surface f is
# the trilinear interpolant, and between (2,8,7) and (4,8,7) f decreases in x.
case_gradient_points_out_of_the_box() {
  input_f
  printf '11.5 1.4 11.4\n' > p.txt
  IN=p.txt expect 0 implicit-eval box-f.nrrd - --gradient
  read -r f gx gy gz < out.txt
  [[ -n "$gz" ]] || fail "--gradient prints f gx gy gz"
  python3 -c "import sys; sys.exit(not float(sys.argv[1]) < 0)" "$gx" || fail "df/dx = $gx should be negative entering the box"
}

case_outside_the_domain_error_or_nan() {
  input_f
printf '9.9 1.4 11.4\n' > outside.txt
expect 1 implicit-eval box-f.nrrd outside.txt
grep -q "outside the domain" err.txt || fail "outside message"
expect 0 implicit-eval box-f.nrrd outside.txt --allow-outside
grep -qx "nan" out.txt || fail "--allow-outside prints nan"
}

case_random_same_checksum_any_threads() {
  input_f
expect 0 implicit-eval box-f.nrrd --random 200000 --seed 7 --threads 1 --stats r1.json
expect 0 implicit-eval box-f.nrrd --random 200000 --seed 7 --threads 2 --stats r2.json
expect 0 implicit-eval box-f.nrrd --random 200000 --seed 7 --gradient --stats r3.json
c1=$(grep '"checksum"' r1.json)
c2=$(grep '"checksum"' r2.json)
[[ "$c1" == "$c2" ]] || fail "checksum depends on threads: $c1 vs $c2"
  [[ $(json r1.json evaluations) == 200000 ]] || fail "not 200000 evaluations"
  [[ $(json r3.json gradient_checksum) != "$(json r1.json checksum)" ]] || fail "no gradient checksum"
}

case_threads_do_not_change_the_output() {
  input box.nrrd
expect 0 wc2implicit box.nrrd box-t1.nrrd --threads 1
expect 0 wc2implicit box.nrrd box-t2.nrrd --threads 2
cmp -s box-t1.nrrd box-t2.nrrd || fail "output depends on --threads"
}

case_stdin_stdout_are_the_files() {
  input box.nrrd
  expect 0 wc2implicit box.nrrd file.nrrd
  OUT=stdout.nrrd expect 0 wc2implicit box.nrrd -
  cmp -s stdout.nrrd file.nrrd || fail "OUT - differs from the file output"
  IN=box.nrrd expect 0 wc2implicit - stdin.nrrd
  cmp -s stdin.nrrd file.nrrd || fail "IN - differs from the file input"
  # implicit-eval: IMPLICIT - and POINTS -, values to -o FILE or stdout.
  printf '12 1.4 11.4\n11 1.4 11.4\n' > p.txt
  expect 0 implicit-eval file.nrrd p.txt -o v-file.txt
  IN=file.nrrd OUT=v-stdout.txt expect 0 implicit-eval - p.txt
  cmp -s v-file.txt v-stdout.txt || fail "implicit-eval - differs from the file"
  IN=p.txt OUT=v-stdin.txt expect 0 implicit-eval file.nrrd -
  cmp -s v-file.txt v-stdin.txt || fail "implicit-eval POINTS - differs from the file"
}

case_bad_input_exit_1_2_without_output() {
  input_f; input critical.nrrd
  printf '12 1.4 11.4\n' > pts.txt
expect 1 wc2implicit critical.nrrd x.nrrd
grep -q "img2wc" err.txt || fail "the not-well-composed message should name img2wc"
[[ ! -e x.nrrd ]] || fail "output written for a refused input"
head -c 200 box.nrrd > truncated.nrrd
expect 1 wc2implicit truncated.nrrd x.nrrd
expect 1 wc2implicit "$DATA/BinaryImage.png" x.nrrd
expect 1 wc2implicit missing.nrrd x.nrrd
expect 2 wc2implicit box.nrrd x.vtk
expect 2 wc2implicit box.nrrd
expect 1 implicit-eval box.nrrd pts.txt
grep -q "pu-implicit" err.txt || fail "a plain image is not an implicit file"
printf '1 2\n' > bad.txt
expect 1 implicit-eval box-f.nrrd bad.txt
printf '12 1.4 nan\n' > bad.txt
expect 1 implicit-eval box-f.nrrd bad.txt
head -c 300 box-f.nrrd > truncated-f.nrrd
expect 1 implicit-eval truncated-f.nrrd pts.txt
expect 2 implicit-eval box-f.nrrd pts.txt --random 10
}

case_samples_through_img2wc_f_equals_g() {
  expect 1 wc2implicit "$DATA/bunny00-96.nrrd" x.nrrd
  grep -q "img2wc" err.txt || fail "bunny: message should name img2wc"
  local name
  for name in bunny00-96 elephant-96; do
    expect 0 img2wc "$DATA/$name.nrrd" "$name-wc.nrrd" -q || continue
    expect 0 wc2implicit "$name-wc.nrrd" "$name-f.nrrd" || continue
    # f = g at voxel centres: read g back with a small independent NRRD
    # reader, evaluate f at 200 random centres (world coordinates).
    python3 - "$name-f.nrrd" centres.txt expected.txt <<'PY' > py.txt 2>&1 || fail "$name: $(tail -1 py.txt)"
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
# Every voxel centre is at least half a voxel from the voxel faces, and some
# lie exactly there; d (the header's imgmesh_d) stays within delta/5.
delta = min(abs(v) for v in dirs[0] + dirs[1] + dirs[2] if v)
d = [float(x) for x in re.search(rb"imgmesh_d:=([^\n]*)", raw[:end]).group(1).split()]
gmin = min(abs(v) for v in g)
assert abs(gmin - delta / 2) <= 1e-6 * delta, "g_min %r, want half the spacing %r" % (gmin, delta)
assert all(0 < x <= delta / 5 for x in d), "d %r not in (0, delta/5]" % (d,)
PY
    expect 0 implicit-eval "$name-f.nrrd" centres.txt
    paste out.txt expected.txt | awk '{ d = $1 - $2; if (d < 0) d = -d; if (d > 1e-6 || ($1 < 0) != ($2 < 0)) bad++ }
      END { exit bad > 0 }' || fail "$name: f differs from g at a voxel centre"
  done
}

run_cases "$@"
