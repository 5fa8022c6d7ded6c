#!/bin/bash
# tri2quad end to end: a real image through img2poly and poly2tri (when they
# are built), a hand-made constrained mesh, every output format, and bad
# input (dangling constraint edge, truncated file, usage errors).
set -u
mkdir -p "$TMP"
cd "$TMP" || exit 1
fail() { echo "FAIL: $*" >&2; exit 1; }
T="$BIN/tri2quad"
[ -x "$T" ] || fail "no $T"

# Statistic from a --stats JSON (first match, numbers and booleans).
stat() { sed -n "s/^ *\"$1\": *\([^,]*\),*$/\1/p" "$2" | head -1; }

check_stats() {  # stats file: strictly convex and within the size bounds
  [ "$(stat non_convex "$1")" = 0 ] || fail "$1: non-convex quads"
  [ "$(stat within_bounds "$1")" = true ] || fail "$1: size bounds exceeded"
  q=$(stat quads "$1"); s=$(stat steiner_points "$1")
  qb=$(stat quad_bound "$1"); sb=$(stat steiner_bound "$1")
  [ "$q" -le "$qb" ] && [ "$s" -le "$sb" ] || fail "$1: bounds"
}

# 1. A real image through the upstream tools (all built with the suite).
for t in img2poly poly2tri; do [ -x "$BIN/$t" ] || fail "no $BIN/$t"; done
if [ -x "$BIN/img2poly" ] && [ -x "$BIN/poly2tri" ]; then
  "$BIN/img2poly" -q "$DATA/RatLungSlice1.mha" lung.poly --threshold 100 || fail "img2poly"
  "$BIN/poly2tri" -q lung.poly lung.1.ele --min-angle 20 || fail "poly2tri"
  "$T" -q lung.1.ele lung.q.ele --svg lung.q.svg --stats lung.json || fail "tri2quad on the lung mesh"
  check_stats lung.json
  grep -v '^ *#' lung.q.ele | head -1 | awk '{ if ($2 != 4) exit 1 }' || fail "lung.q.ele: not 4 nodes an element"
  [ -s lung.q.node ] && [ -s lung.q.poly ] && [ -s lung.q.svg ] || fail "lung outputs missing"
  # Every element line has 4 node ids (plus the region attribute).
  grep -v '^ *#' lung.q.ele | tail -n +2 | awk 'NF > 0 && NF < 5 { exit 1 }' || fail "short element line"
fi

# 2. A hand-made constrained mesh: a square with an interior constraint loop
# (a diamond around the centre), 1-based ids like Triangle's.
cat > sq.node <<'N'
9 2 0 0
1 0 0
2 4 0
3 4 4
4 0 4
5 2 1
6 3 2
7 2 3
8 1 2
9 2 2
N
cat > sq.ele <<'N'
12 3 1
1 1 2 5 1
2 2 6 5 1
3 2 3 6 1
4 3 7 6 1
5 3 4 7 1
6 4 8 7 1
7 4 1 8 1
8 1 5 8 1
9 5 6 9 2
10 6 7 9 2
11 7 8 9 2
12 8 5 9 2
N
cat > sq.poly <<'N'
0 2 0 1
8 1
1 1 2 1
2 2 3 1
3 3 4 1
4 4 1 1
5 5 6 2
6 6 7 2
7 7 8 2
8 8 5 2
0
N
"$T" -q sq.ele sq.q.ele --stats sq.json || fail "tri2quad on sq"
check_stats sq.json
[ "$(stat components sq.json)" = 2 ] || fail "sq: expected 2 components"
[ "$(stat triangles sq.json)" = 12 ] || fail "sq: 12 triangles"
# The constraints are kept with their markers: for each marker, every output
# segment lies on an input segment of that marker and their lengths add up
# to the input's (the square's sides 1, the interior loop 5-6-7-8 2).
python3 - sq.node sq.poly sq.q.node sq.q.poly <<'PY' || fail "sq.q.poly: constraint segments or markers lost"
import math, sys
def rows(path):
    return [l.split('#', 1)[0].split() for l in open(path) if l.split('#', 1)[0].split()]
def segments(node, poly):
    N = rows(node); pts = {r[0]: (float(r[1]), float(r[2])) for r in N[1:1 + int(N[0][0])]}
    P = rows(poly); k = 1 + int(P[0][0]); ns = int(P[k][0])
    return [(pts[r[1]], pts[r[2]], int(r[3])) for r in P[k + 1:k + 1 + ns]]
def on(p, a, b):  # p on the closed segment ab
    ux, uy, vx, vy = b[0] - a[0], b[1] - a[1], p[0] - a[0], p[1] - a[1]
    l2 = ux * ux + uy * uy; t = (ux * vx + uy * vy) / l2
    return abs(ux * vy - uy * vx) <= 1e-9 * l2 and -1e-9 <= t <= 1 + 1e-9
inp, out = segments(*sys.argv[1:3]), segments(*sys.argv[3:5])
ok = True
for m in sorted({s[2] for s in inp}):
    I = [s for s in inp if s[2] == m]; O = [s for s in out if s[2] == m]
    ok &= all(any(on(a, c, d) and on(b, c, d) for c, d, _ in I) for a, b, _ in O)
    ok &= abs(sum(math.dist(a, b) for a, b, _ in O) - sum(math.dist(a, b) for a, b, _ in I)) < 1e-9
ok &= {s[2] for s in out} == {s[2] for s in inp} == {1, 2}
sys.exit(0 if ok else 1)
PY
# Regions carried: both attributes 1 and 2 appear on quads.
grep -v '^ *#' sq.q.ele | tail -n +2 | awk 'NF >= 6 { seen[$6] = 1 } END { exit !(seen[1] && seen[2]) }' \
  || fail "region attributes not carried"
for ext in off vtk msh svg; do
  "$T" -q sq.ele "sq.q.$ext" || fail "output .$ext"
  [ -s "sq.q.$ext" ] || fail "empty .$ext"
done
grep -q '^\$MeshFormat' sq.q.msh || fail "msh header"
# OFF through pipes.
"$T" -q sq.q.off - < /dev/null > /dev/null 2>&1 && fail "quad OFF accepted as triangles"
"$T" -q sq.ele - | head -1 | grep -q '^OFF' || fail "OFF on stdout"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' | "$T" -q - - | head -2 | tail -1 | awk '{ if ($2 != 5) exit 1 }' \
  || fail "one triangle from stdin: expected Joe's 5 quads"
"$T" -q sq.ele sq.o.ele --allow-outside --stats sq.o.json || fail "--allow-outside"
check_stats sq.o.json

# 3. Bad input: a dangling constraint edge (Fig. 3.26) names the edge.
cat > bad.node <<'N'
5 2 0 0
1 0 0
2 2 0
3 2 2
4 0 2
5 1 1
N
cat > bad.ele <<'N'
4 3 0
1 1 2 5
2 2 3 5
3 3 4 5
4 4 1 5
N
printf '0 2 0 1\n1 1\n1 1 5 1\n0\n' > bad.poly
for pa in 0 40; do  # pairs first refuses it the same way (its pairs would hide it)
  "$T" bad.ele bad.q.ele --pair-above $pa 2> bad.err; rc=$?
  [ $rc = 1 ] || fail "dangling edge, --pair-above $pa: exit $rc, expected 1"
  grep -Eq '\((1, 5|5, 1)\)' bad.err || fail "dangling edge not named: $(cat bad.err)"
  [ "$(wc -l < bad.err)" = 1 ] || fail "error is not one line"
  [ ! -e bad.q.ele ] || fail "output written on error"
done
# A dangling constraint between triangles that pairs first would merge
# (every lattice square across its diagonal): still refused.
printf '9 2 0 0\n1 0 0\n2 1 0\n3 2 0\n4 0 1\n5 1 1\n6 2 1\n7 0 2\n8 1 2\n9 2 2\n' > bad2.node
printf '8 3 0\n1 1 2 5\n2 1 5 4\n3 2 3 6\n4 2 6 5\n5 4 5 8\n6 4 8 7\n7 5 6 9\n8 5 9 8\n' > bad2.ele
printf '0 2 0 1\n1 1\n1 2 5 1\n0\n' > bad2.poly
"$T" bad2.ele bad2.q.ele --pair-above 40 2> bad.err; rc=$?
[ $rc = 1 ] || fail "dangling edge under merged pairs: exit $rc, expected 1"
grep -Eq '\((2, 5|5, 2)\)' bad.err || fail "dangling edge not named: $(cat bad.err)"
[ ! -e bad2.q.ele ] || fail "output written on error"

# Truncated input.
head -3 sq.ele > trunc.ele; cp sq.node trunc.node
"$T" trunc.ele trunc.q.ele 2> trunc.err; rc=$?
[ $rc = 1 ] || fail "truncated .ele: exit $rc"
# Missing file, unknown output extension, unknown option: exit 1, 2, 2.
"$T" nothere.ele x.ele 2>/dev/null; [ $? = 1 ] || fail "missing input"
"$T" sq.ele x.txt 2>/dev/null; [ $? = 2 ] || fail "bad output extension"
"$T" sq.ele x.ele --bogus 2>/dev/null; [ $? = 2 ] || fail "unknown option"
# Quads as input are refused.
"$T" sq.q.ele x.ele 2>/dev/null; [ $? = 1 ] || fail "quad input accepted"
echo "tri2quad e2e: ok"
