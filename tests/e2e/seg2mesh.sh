#!/bin/bash
# seg2mesh end to end on a fixed three-label image (labels_image.py: a ball,
# a box touching it, a solid torus): every label's faces, cut out of the one
# output file by their label, are checked against that label's own
# well-composed image by surface_check (closed, oriented, the voxel
# boundary's components and Euler characteristics, ratio bound); labels and
# component ids read back; --labels, --jobs, the exit-3 and error contracts.
set -euo pipefail
mkdir -p "$TMP"
cd "$TMP"
rm -rf ./*
fail() { echo "FAIL: $*" >&2; exit 1; }
here=$(dirname "$0")
tool="$BIN/seg2mesh"
check="$BIN/../tests/unit/surface/surface_check"
[ -x "$tool" ] || fail "no $tool"

python3 "$here/labels_image.py" labels.nrrd
"$tool" -q labels.nrrd all.ply --jobs 2 --stats s.json || fail "exit $?"
"$tool" -q labels.nrrd all.msh --jobs 1
"$tool" -q labels.nrrd all1.ply --jobs 1
# Cut each label's faces out (its own vertices) as OFF; print the labels and
# the number of component ids, or "inward" for a label whose enclosed
# volume is not positive (outward orientation).
cat > cut.py <<'PY'
import sys; sys.path.insert(0, sys.argv[2]); import surface_read as r
m = r.read(sys.argv[1])
lab = m['label'] if m['label'] is not None else m['physical']
for L in sorted(set(lab)):
    faces = [t for t, l in zip(m['triangles'], lab) if l == L]
    used = sorted({v for t in faces for v in t})
    new = {v: i for i, v in enumerate(used)}
    with open('%s.%d.off' % (sys.argv[1], L), 'w') as f:
        f.write('OFF\n%d %d 0\n' % (len(used), len(faces)))
        f.writelines('%.17g %.17g %.17g\n' % m['points'][v] for v in used)
        f.writelines('3 %d %d %d\n' % tuple(new[v] for v in t) for t in faces)
    comps = {c for c, l in zip(m['component'], lab) if l == L}
    P = m['points']
    det = lambda a, b, c: (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                           + a[2] * (b[0] * c[1] - b[1] * c[0]))
    volume = sum(det(P[a], P[b], P[c]) for a, b, c in faces) / 6
    print(L, len(comps) if volume > 0 else 'inward', end=' ')
print()
PY
[ "$(python3 cut.py all.ply "$here")" = "1 1 2 1 5 1 " ] || fail "all.ply: labels 1 2 5 with one component each expected"
[ "$(python3 cut.py all.msh "$here")" = "1 1 2 1 5 1 " ] || fail "all.msh: physical groups 1 2 5 expected"
for L in 1 2 5; do
  "$BIN/img2wc" -q labels.nrrd --label $L wc$L.nrrd
  "$check" all.ply.$L.off wc$L.nrrd 2 > c.txt || { cat c.txt; fail "label $L's surface not certified"; }
  expected=$([ $L = 5 ] && echo 0 || echo 2)
  grep -q "euler $expected expected $expected " c.txt || { cat c.txt; fail "label $L: Euler characteristic"; }
  "$check" all.msh.$L.off wc$L.nrrd 2 > /dev/null || fail "label $L's surface in .msh (--jobs 1)"
done
# --jobs 1: each label as the pipeline makes it (byte for byte, seeded alike).
python3 cut.py all1.ply "$here" > /dev/null
for L in 1 2 5; do
  "$BIN/wc2implicit" -q wc$L.nrrd - | "$BIN/implicit2mesh" -q --threads 1 - pipe$L.ply
  python3 - pipe$L.ply all1.ply.$L.off "$here" <<'PY' || fail "label $L: seg2mesh --jobs 1 is not the pipeline's mesh"
import sys; sys.path.insert(0, sys.argv[3]); import surface_read as r
a, b = r.read(sys.argv[1]), r.read(sys.argv[2])
assert a['triangles'] == b['triangles'] and max(abs(x - y) for p, q in zip(a['points'], b['points']) for x, y in zip(p, q)) < 1e-9
PY
done
python3 -c "
import json; d = json.load(open('s.json'))
assert d['all_certified'] is True and [l['label'] for l in d['labels']] == [1, 2, 5], d
assert all(l['certified'] and l['topology_matches'] for l in d['labels'])" || fail "stats"

# --labels: a subset; an absent label is an error naming those present.
"$tool" -q labels.nrrd some.ply --labels 5,2
[ "$(python3 cut.py some.ply "$here")" = "2 1 5 1 " ] || fail "--labels 5,2"
set +e
"$tool" labels.nrrd bad.ply --labels 1,9 2> err.txt; rc=$?
set -e
[ $rc = 1 ] && [ ! -e bad.ply ] && grep -q "^seg2mesh: .*label 9 does not occur (labels present: 1 2 5)" err.txt \
  || { cat err.txt; fail "absent label: exit $rc"; }
set +e
"$tool" labels.nrrd bad.ply --labels 1,x 2> err.txt; rc=$?
set -e
[ $rc = 2 ] && [ ! -e bad.ply ] || fail "--labels 1,x: exit $rc"
# A guarantee that fails for one label (too few points allowed): the file is
# written, exit 3, and the label is named.
set +e
"$tool" labels.nrrd cap.ply --max-points 40 2> err.txt; rc=$?
set -e
[ $rc = 3 ] && [ -s cap.ply ] || { cat err.txt; fail "--max-points 40: exit $rc, want 3 with the file"; }
grep -q "^seg2mesh: .*label [125]: " err.txt || { cat err.txt; fail "the failing label is not named"; }
echo ok
