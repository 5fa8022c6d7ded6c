#!/bin/bash
# implicit2mesh end to end: the real pipeline on a bundled image, the
# topology certificate checked independently (surface_check computes bdCA(X)
# of the well-composed image from its boundary faces), exit codes, atomic
# outputs, and share/examples/Makefile on a bundled multi-label image.
set -euo pipefail
mkdir -p "$TMP"
cd "$TMP"
rm -rf ./*
tool="$BIN/implicit2mesh"
check="$BIN/../tests/unit/surface/surface_check"
fail() { echo "FAIL: $*" >&2; exit 1; }
[ -x "$tool" ] || fail "no $tool"
[ -x "$check" ] || fail "no $check"

expect_status() {  # expect_status CODE command...
  local want=$1; shift
  set +e; "$@" 2>err.txt; local got=$?; set -e
  [ "$got" = "$want" ] || { cat err.txt >&2; fail "exit $got, want $want: $*"; }
  [ "$want" = 0 ] || [ "$(wc -l < err.txt)" -ge 1 ] || fail "no message on stderr: $*"
}

# Usage errors (2) and bad input (1) leave no output behind.
expect_status 2 "$tool"
expect_status 2 "$tool" in.nrrd out.xyz
expect_status 2 "$tool" in.nrrd out.off --ratio 1.1
expect_status 2 "$tool" in.nrrd out.off --roughness 0.2
expect_status 2 "$tool" in.nrrd out.off --max-distance -1
expect_status 1 "$tool" missing.nrrd out.off
expect_status 1 "$tool" "$DATA/bunny00-96.nrrd" out.off    # not an implicit function file
# The reason itself: every message of the tool starts with "implicit2mesh:".
grep -q "not an implicit function file" err.txt || { cat err.txt >&2; fail "a non-implicit file is not named as such"; }
: > empty.nrrd
expect_status 1 "$tool" empty.nrrd out.off
[ ! -e out.off ] || fail "output written on error"

for t in img2wc wc2implicit; do [ -x "$BIN/$t" ] || fail "no $BIN/$t: the pipeline part needs it"; done

# The pipeline through pipes, default bounds; then rho_0 = 1.2.
"$BIN/img2wc" -q "$DATA/bunny00-96.nrrd" bunny-wc.nrrd
"$BIN/img2wc" -q "$DATA/bunny00-96.nrrd" - | "$BIN/wc2implicit" -q - - | "$tool" -q - bunny.ply --stats stats.json
"$check" bunny.ply bunny-wc.nrrd 2 || fail "bunny: topology or ratio"
grep -q '"topology_matches": true' stats.json || fail "stats: topology_matches"
grep -q '"restricted_delaunay_violations": 0' stats.json || fail "stats: restricted Delaunay"
"$BIN/wc2implicit" -q bunny-wc.nrrd bunny-f.nrrd
"$tool" -q bunny-f.nrrd bunny12.off --ratio 1.2 --normals
"$check" bunny12.off bunny-wc.nrrd 1.2 || fail "bunny at rho_0 = 1.2"
"$tool" -q bunny-f.nrrd - > stdout.off
[ "$(head -1 stdout.off)" = OFF ] || fail "OFF on stdout"
"$check" stdout.off bunny-wc.nrrd 2 || fail "OFF on stdout: topology"
"$tool" -q bunny-f.nrrd bunny-n.ply --normals --max-distance 0.02
"$check" bunny-n.ply bunny-wc.nrrd 2 || fail "bunny with normals and --max-distance"
# The normals read back: every one unit and on the outer side of the
# (outward, checked above) triangles around its vertex.
python3 - bunny-n.ply <<'PY' || fail "bunny-n.ply: normals not unit or not outward"
import math, struct, sys
b = open(sys.argv[1], 'rb').read()
h = b[:b.index(b'end_header\n') + 11].decode().split('\n')
assert 'format binary_little_endian 1.0' in h and h.count('property float nx') == 1
nv = int(next(l for l in h if l.startswith('element vertex')).split()[2])
nf = int(next(l for l in h if l.startswith('element face')).split()[2])
at = len('\n'.join(h))
V = [struct.unpack_from('<6f', b, at + 24 * i) for i in range(nv)]
at += 24 * nv
acc = [[0.0, 0.0, 0.0] for _ in range(nv)]
for k in range(nf):
    assert b[at] == 3
    i, j, l = struct.unpack_from('<3i', b, at + 1); at += 13
    p, q, r = V[i], V[j], V[l]
    u = [q[m] - p[m] for m in range(3)]; w = [r[m] - p[m] for m in range(3)]
    n = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
    for v in (i, j, l):
        for m in range(3): acc[v][m] += n[m]
assert at == len(b)
bad = 0
for v, a in zip(V, acc):
    n = v[3:]
    if abs(math.hypot(*n) - 1) > 1e-5: sys.exit('normal not unit: %r' % (n,))
    if sum(n[m] * a[m] for m in range(3)) <= 0: bad += 1
sys.exit('%d of %d normals point inward' % (bad, nv) if bad else 0)
PY

# The FacetCycle checks run on --threads threads: same mesh for 1 and 2.
"$tool" -q bunny-f.nrrd bunny-t1.off --threads 1
"$tool" -q bunny-f.nrrd bunny-t2.off --threads 2
cmp -s bunny-t1.off bunny-t2.off || fail "--threads changes the mesh"

# Real brain tissue: a noisy k-means class (289 components, one of genus
# 1482; among them thin rods whose cross-sections nearly fill a Voronoi facet).
"$BIN/img2wc" -q "$DATA/brain-kmeans-labels.nii.gz" --label 5 brain-wc.nrrd
"$BIN/wc2implicit" -q brain-wc.nrrd brain-f.nrrd
"$tool" -q brain-f.nrrd brain.off --roughness 1.5708 --stats brain.json
"$check" brain.off brain-wc.nrrd 2 || fail "brain label 5: topology or ratio"
grep -q '"restricted_delaunay_violations": 0' brain.json || fail "brain: restricted Delaunay"
# The thesis's TOPOLOGY steps suffice here: the certificate passes at once.
grep -q '"topology_fallback_rounds": 0' brain.json || fail "brain: certificate needed repairs"

# A real organ: CGAL's liver CT labels, the whole organ (35 components, the
# liver's surface of Euler characteristic -6 around its vessels), at the
# default settings, with anisotropic voxels (0.62 x 0.62 x 1.33 mm).
"$BIN/img2wc" -q "$DATA/liver-labels.nrrd" --threshold 1 liver-wc.nrrd
"$BIN/wc2implicit" -q liver-wc.nrrd liver-f.nrrd
"$tool" -q liver-f.nrrd liver.ply --threads 2 --stats liver.json
"$check" liver.ply liver-wc.nrrd 2 || fail "liver: topology, self-intersection or ratio"
grep -q '"topology_fallback_rounds": 0' liver.json || fail "liver: certificate needed repairs"

# --max-points: the mesh is written, status 3, the failed guarantee named.
expect_status 3 "$tool" bunny-f.nrrd small.off --max-points 40
grep -q "max-points" err.txt || fail "max-points not named"
[ -s small.off ] || fail "max-points: no mesh written"

# The certificate's repairs (tests switch TOPOLOGY off) on a ball and a
# torus: the fallback restores the topology, counted; with no repair round
# the mesh is written, status 3, the failing component named.
python3 - <<'P'
import math
b = bytearray()
for z in range(24):
    for y in range(24):
        for x in range(40):
            ball = (x - 10) ** 2 + (y - 11.5) ** 2 + (z - 11.5) ** 2 <= 36
            torus = (math.hypot(x - 29, y - 11.5) - 6) ** 2 + (z - 11.5) ** 2 <= 2.5 ** 2
            b.append(1 if ball or torus else 0)
open('two.nrrd', 'wb').write(b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 40 24 24\nencoding: raw\n\n" + bytes(b))
P
"$BIN/img2wc" -q two.nrrd two-wc.nrrd
"$BIN/wc2implicit" -q two-wc.nrrd two-f.nrrd
"$tool" -q two-f.nrrd nt.off --skip-topology-steps --stats nt.json
"$check" nt.off two-wc.nrrd 2 || fail "fallback: topology not restored"
grep -q '"topology_fallback_rounds": [1-9]' nt.json || fail "fallback: no round counted"
grep -q '"topology_fallback_points": [1-9]' nt.json || fail "fallback: no point counted"
expect_status 3 "$tool" two-f.nrrd nt0.off --skip-topology-steps --fallback-rounds 0
grep -q "mesh component [0-9]*: euler 1, its bdCA(X) component [0-9]* has 0" err.txt || fail "fallback-rounds 0: $(cat err.txt)"
[ -s nt0.off ] || fail "fallback-rounds 0: no mesh written"

# share/examples/Makefile on the bundled liver labels: vessels (127, 29
# components), parenchyma (255) and label 85, one mesh per label, in parallel.
make -s -f "$SRC/share/examples/Makefile" SCAN="$DATA/liver-labels.nrrd" LABELS="85 127 255" BIN="$BIN/" OUT=ex -j2
for l in 85 127 255; do
  "$check" "ex/label-$l.ply" "ex/label-$l.wc.nrrd" 2 || fail "example label $l"
  [ -s "ex/label-$l.json" ] || fail "example label $l: no --stats report"
done
# The same workflow as share/examples/Snakefile, where Snakemake is installed
# (Debian package snakemake; not needed by the build or CI).
if command -v snakemake >/dev/null; then
  snakemake -q -s "$SRC/share/examples/Snakefile" --cores 2 -d sk \
    --config scan="$DATA/liver-labels.nrrd" labels="85" bin="$BIN/" out=ex >/dev/null 2>&1 || fail "Snakefile"
  grep -q '"topology_matches": true' sk/ex/label-85.json || fail "Snakefile: topology"
fi
echo "implicit2mesh e2e: ok"
