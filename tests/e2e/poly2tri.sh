#!/usr/bin/env bash
# poly2tri end to end: Triangle's .poly conventions (comments, ids from 1,
# holes, regional attributes, markers), OFF polygons, angle and size bounds,
# lattices, outputs readable back (.ele/.node/.poly, .off, .vtk, .msh, .svg
# holding the same triangles), and bad input (crossing segments, dangling
# id, truncated file) giving one line, exit 1 and no output. Meshes are
# checked by planar_check.py (CCW, conformity to the segments, angles).
source "$(dirname "$0")/lib.sh"
CHECK=$E2E/planar_check.py

# A 10 x 10 square, ids from 1, a square hole (4..6)^2, a dividing segment at
# y = 2 with its own marker, two regions (below: 10, above: 20), comments.
square() {
cat > sq.poly <<'PEOF'
# vertices: id x y, one marker
10 2 0 1
1 0 0 5   # corner
2 10 0 5
3 10 10 5
4 0 10 5
5 4 4 0
6 6 4 0
7 6 6 0
8 4 6 0
9 0 2 0
10 10 2 0

11 1
1 1 2 1
2 2 10 1
3 10 3 1
4 3 4 1
5 4 9 1
6 9 1 1
7 5 6 2
8 6 7 2
9 7 8 2
10 8 5 2
11 9 10 3
# one hole
1
1 5 5
# two regions: x y attribute max-area
2
1 1 1 10 -1
2 1 9 20 -1
PEOF
}

case_square_hole_regions_markers_ids() {
  square
  expect 0 poly2tri sq.poly sq.1.ele --svg sq.svg
python3 "$CHECK" sq.1.ele sq.poly 20.7 > c.txt || { fail "$(cat c.txt) sq mesh"; }
python3 - <<'PYEOF' || fail "sq: area, hole, regions, markers, ids"
L = lambda f: [l for l in (x.split('#')[0].split() for x in open(f)) if l]
N, E, P = L("sq.1.node"), L("sq.1.ele"), L("sq.1.poly")
assert N[1][0] == '1' and E[1][0] == '1', "ids do not start at 1 like the input"
pts = {int(r[0]): (float(r[1]), float(r[2]), int(r[3])) for r in N[1:]}
area = 0
for r in E[1:]:
    a, b, c = (pts[int(t)] for t in r[1:4])
    A = ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) / 2
    area += A
    cx, cy = (a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3
    assert not (4 < cx < 6 and 4 < cy < 6), "a triangle in the hole"
    assert float(r[4]) == (10 if cy < 2 else 20), (cx, cy, r[4])
assert abs(area - 96) < 1e-9, area
# subsegments keep their markers; vertices on a segment carry its marker
ns = int(P[1][0])
for r in P[2:2 + ns]:
    a, b, m = pts[int(r[1])], pts[int(r[2])], int(r[3])
    if m == 2: assert max(abs((a[0] + b[0]) / 2 - 5), abs((a[1] + b[1]) / 2 - 5)) > 0.99
    if m == 3: assert a[1] == 2 and b[1] == 2
for x, y, m in pts.values():
    if (x, y) in [(0, 0), (10, 0), (10, 10), (0, 10)]: assert m == 5, (x, y, m)
    elif abs(max(abs(x - 5), abs(y - 5)) - 1) < 1e-12: assert m == 2, (x, y, m)
    elif y == 2 and 0 < x < 10: assert m == 3, (x, y, m)
PYEOF
  [[ $(grep -c '<polygon' sq.svg) == $(count sq.1.ele) ]] || fail "the SVG does not draw every triangle"
}

case_angle_area_edge_bounds() {
  square
expect 0 poly2tri sq.poly sq.2.ele --min-angle 30 --max-area 0.25
python3 "$CHECK" sq.2.ele sq.poly 30 > c.txt || { fail "$(cat c.txt) 30 degrees"; }
python3 - <<'PYEOF' || fail "max area"
L = lambda f: [l for l in (x.split('#')[0].split() for x in open(f)) if l]
N, E = L("sq.2.node"), L("sq.2.ele")
pts = {int(r[0]): (float(r[1]), float(r[2])) for r in N[1:]}
for r in E[1:]:
    a, b, c = (pts[int(t)] for t in r[1:4])
    assert ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) / 2 <= 0.25 + 1e-12
PYEOF
expect 0 poly2tri sq.poly sq.3.ele --max-edge 0.5 --min-angle 0
python3 - <<'PYEOF' || fail "max edge"
import math
L = lambda f: [l for l in (x.split('#')[0].split() for x in open(f)) if l]
N, E = L("sq.3.node"), L("sq.3.ele")
pts = {int(r[0]): (float(r[1]), float(r[2])) for r in N[1:]}
for r in E[1:]:
    p = [pts[int(t)] for t in r[1:4]]
    assert max(math.dist(p[k], p[(k + 1) % 3]) for k in range(3)) <= 0.5 + 1e-12
PYEOF
  # A sharp input angle (about 6 degrees): the bound holds away from it.
printf '4 2 0 0\n0 0 0\n1 10 0\n2 10 1.1\n3 3 4\n4 0\n0 0 1\n1 1 2\n2 2 3\n3 3 0\n0\n' > sharp.poly
expect 0 poly2tri sharp.poly sharp.1.ele
python3 "$CHECK" sharp.1.ele sharp.poly 20.7 > c.txt || { fail "$(cat c.txt) sharp"; }
}

case_output_poly_and_off_polygons_read_back() {
  square
  expect 0 poly2tri sq.poly sq.1.ele
# The output .poly (vertices in the .node) is itself a valid input.
expect 0 poly2tri sq.1.poly sq.4.ele
# OFF polygons: a square with a square inside it (two polygons).
printf 'OFF\n8 2 0\n0 0 0\n4 0 0\n4 4 0\n0 4 0\n1 1 0\n3 1 0\n3 3 0\n1 3 0\n4 0 1 2 3\n4 4 5 6 7\n' > sq.off
expect 0 poly2tri sq.off off.1.ele
printf '0 2 0 0\n8 0\n0 0 1\n1 1 2\n2 2 3\n3 3 0\n4 4 5\n5 5 6\n6 6 7\n7 7 4\n' > off.poly
printf '8 2 0 0\n0 0 0\n1 4 0\n2 4 4\n3 0 4\n4 1 1\n5 3 1\n6 3 3\n7 1 3\n' > off.node
python3 "$CHECK" off.1.ele off.poly 20.7 > c.txt || { fail "$(cat c.txt) OFF input"; }
  # The output .poly (vertices in the .node) gives the same mesh again.
  python3 "$CHECK" sq.4.ele sq.poly 20.7 > c.txt || fail "$(cat c.txt) sq.1.poly as input"
}

case_formats_off_vtk_msh_svg_hold_the_triangles() {
  square
  expect 0 poly2tri sq.poly ref.1.ele
  local t; t=$(count ref.1.ele)
  for ext in off vtk msh svg; do expect 0 poly2tri sq.poly "sq.$ext" --ascii; done
  [[ $(sed -n 2p sq.off | cut -d' ' -f2) == "$t" && $(tail -n "$t" sq.off | grep -c '^3 ') == "$t" ]] || fail ".off: not $t triangles"
  grep -q "^CELLS $t " sq.vtk || fail ".vtk: not $t cells"
  grep -q '^\$MeshFormat' sq.msh && [[ $(awk '/^\$Elements/ { e = 1; getline; next } /^\$EndElements/ { e = 0 } e && $2 == 2' sq.msh | wc -l) == "$t" ]] ||
    fail ".msh: not $t triangles"
  [[ $(grep -c '<polygon' sq.svg) == "$t" ]] || fail ".svg: not $t polygons"
  for f in sq.vtk sq.msh sq.svg; do whole "$f"; done
  # The default .vtk is binary (big-endian legacy VTK): meshio reads the
  # same points, cells and cell data as from the --ascii file.
  expect 0 poly2tri sq.poly sqb.vtk
  head -3 sqb.vtk | grep -aqx BINARY || fail "sqb.vtk: not binary"
  if /usr/bin/python3 -c 'import meshio' 2> /dev/null; then
    /usr/bin/python3 - > mio.txt 2>&1 <<'PY' || fail "meshio reads the binary .vtk otherwise: $(cat mio.txt)"
import meshio
x, y = meshio.read('sqb.vtk'), meshio.read('sq.vtk')
assert (x.points == y.points).all() and [c.type for c in x.cells] == [c.type for c in y.cells]
assert all((p.data == q.data).all() for p, q in zip(x.cells, y.cells))
assert sorted(x.cell_data) == sorted(y.cell_data) == ['region']
assert all((p == q).all() for k in x.cell_data for p, q in zip(x.cell_data[k], y.cell_data[k]))
assert (x.point_data['marker'] == y.point_data['marker']).all()
PY
  fi
}

# --lattice: the same guarantees (segments, angle, hole, regions, area) with
# the lattice points in, on the square above and on random star polygons
# with a square hole, lattice sides from a twentieth to a half of the size.
case_lattices_keep_every_guarantee() {
  square
expect 0 poly2tri sq.poly sq.l.ele --lattice 0.5
python3 "$CHECK" sq.l.ele sq.poly 20.7 > c.txt || { fail "$(cat c.txt) lattice: sq mesh"; }
# An equilateral lattice of side 0.5 has 2 / (sqrt(3) 0.5^2) = 4.6 points a
# unit area: about 440 in the 96 of the domain.
(( $(count sq.l.node) >= 350 )) || fail "lattice: $(count sq.l.node) vertices for about 440 lattice points"
python3 - <<'PYEOF' || fail "lattice: area, hole, regions"
L = lambda f: [l for l in (x.split('#')[0].split() for x in open(f)) if l]
N, E = L("sq.l.node"), L("sq.l.ele")
pts = {int(r[0]): (float(r[1]), float(r[2])) for r in N[1:]}
area = 0
for r in E[1:]:
    a, b, c = (pts[int(t)] for t in r[1:4])
    area += ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) / 2
    cx, cy = (a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3
    assert not (4 < cx < 6 and 4 < cy < 6), "a triangle in the hole"
    assert float(r[4]) == (10 if cy < 2 else 20), (cx, cy, r[4])
assert not any(4 < x < 6 and 4 < y < 6 for x, y in pts.values()), "a vertex in the hole"
assert abs(area - 96) < 1e-9, area
PYEOF
# --square-lattice: the same guarantees, and the interior is right isosceles
# triangles (halves of the lattice squares; the equilateral lattice's are 60).
expect 0 poly2tri sq.poly sq.s.ele --square-lattice 0.5
python3 "$CHECK" sq.s.ele sq.poly 20.7 > c.txt || { fail "$(cat c.txt) square lattice: sq mesh"; }
python3 - <<'PYEOF' || fail "square lattice: not mostly right isosceles triangles"
import math
L = lambda f: [l for l in (x.split('#')[0].split() for x in open(f)) if l]
N, E = L("sq.s.node"), L("sq.s.ele")
pts = {int(r[0]): (float(r[1]), float(r[2])) for r in N[1:]}
def angles(a, b, c):
    out = []
    for p, q, r in ((a, b, c), (b, c, a), (c, a, b)):
        u, v = (q[0] - p[0], q[1] - p[1]), (r[0] - p[0], r[1] - p[1])
        out.append(math.degrees(math.atan2(abs(u[0] * v[1] - u[1] * v[0]), u[0] * v[0] + u[1] * v[1])))
    return sorted(out)
right = sum(1 for r in E[1:] if all(abs(x - y) < 1e-6 for x, y in zip(angles(*(pts[int(t)] for t in r[1:4])), (45, 45, 90))))
assert right > 0.6 * (len(E) - 1), (right, len(E) - 1)
PYEOF
  local seed side kind
  for seed in 1 2 3 4 5 6; do
  python3 - "$seed" > star.poly <<'PYEOF'
import math, random, sys
r = random.Random(int(sys.argv[1])); n = r.randint(12, 60)
polar = [(5 + 4 * r.random(), 2 * math.pi * (k + 0.8 * r.random()) / n) for k in range(n)]
P = [(10 + q * math.cos(a), 10 + q * math.sin(a)) for q, a in polar]
P += [(9, 9), (11, 9), (11, 11), (9, 11)]
print(len(P), 2, 0, 0)
for k, (x, y) in enumerate(P): print(k, repr(x), repr(y))
print(n + 4, 0)
for k in range(n): print(k, k, (k + 1) % n)
for k in range(4): print(n + k, n + k, n + (k + 1) % 4)
print(1); print(0, 10, 10)
PYEOF
    side=$(python3 -c "import random, sys; print('%.3f' % (1 + 9 * random.Random(int(sys.argv[1])).random()))" "$seed")
  kind=lattice; [[ $((seed % 2)) = 1 ]] && kind=square-lattice  # both lattices keep the angle bound
  expect 0 poly2tri star.poly star.1.ele "--$kind" "$side"
  python3 "$CHECK" star.1.ele star.poly 20.7 > c.txt || { fail "$(cat c.txt) lattice $side, star $seed"; }
  python3 - star.1 <<'PYEOF' || fail "lattice $side, star $seed: hole"
import sys
L = lambda f: [l for l in (x.split('#')[0].split() for x in open(f)) if l]
assert not any(9 < float(r[1]) < 11 and 9 < float(r[2]) < 11 for r in L(sys.argv[1] + ".node")[1:])
PYEOF
done
}

case_lattice_and_size_usage_errors_before_work() {
  square
expect 2 poly2tri sq.poly x.1.ele --lattice 0
expect 2 poly2tri sq.poly x.1.ele --lattice 1 --square-lattice 1
expect 2 poly2tri sq.poly x.1.ele --lattice 0.001 --max-vertices 1000
[[ ! -e x.1.ele ]] || fail "output written on a lattice usage error"
# A size bound beyond --max-vertices is refused at once, not after the refinement.
for bound in "--max-area 1e-9" "--max-edge 1e-5" "--max-area 0.001 --max-vertices 1000"; do
  # shellcheck disable=SC2086  # an option and its value
  expect 2 timeout 10 "$BIN/poly2tri" sq.poly x.1.ele $bound
  grep -q "max-vertices" err.txt || fail "$bound: $(cat err.txt)"
  [[ ! -e x.1.ele ]] || fail "output written on a refused size bound"
done
}

case_bad_input_one_line_exit_1_without_output() {
  square
# Bad input: one line on stderr, exit 1, nothing written.
printf '4 2 0 0\n0 0 0\n1 2 2\n2 2 0\n3 0 2\n3 0\n0 0 1\n1 2 3\n2 0 2\n' > cross.poly
printf '3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n3 0\n0 0 1\n1 1 2\n2 2 7\n' > dangling.poly
head -c 60 sq.poly > trunc.poly
printf '3 2 0 0\n0 0 0\n1 nan 0\n2 0 1\n3 0\n0 0 1\n1 1 2\n2 2 0\n' > nan.poly
for bad in cross dangling trunc nan; do
  expect 1 poly2tri $bad.poly $bad.1.ele
  [[ $(wc -l < err.txt) -eq 1 ]] || fail "$bad: error is not one line"
  grep -q "$bad.poly" err.txt || fail "$bad: the error does not name the file"
  [[ ! -e $bad.1.ele && ! -e $bad.1.node && ! -e $bad.1.poly ]] || fail "$bad: output written"
done
grep -q "line" err.txt || fail "no line number"
expect 1 poly2tri missing.poly m.1.ele
expect 2 poly2tri sq.poly x.1.ele --min-angle 40
expect 2 poly2tri sq.poly x.1.ele --max-area 1 --max-edge 1
expect 2 poly2tri sq.poly x.1.txt
[[ ! -e x.1.ele ]] || fail "output written on usage error"
}

# "-": a .poly on stdin and OFF on stdout are the file input and the .off
# output, byte for byte (also on exit 3); the .off is the .ele's mesh.
case_stdin_stdout_are_the_files() {
  square
  expect 0 poly2tri sq.poly file.off
  OUT=stdout.off expect 0 poly2tri sq.poly -
  cmp -s stdout.off file.off || fail "OUT - differs from OUT file.off"
  IN=sq.poly OUT=stdin.off expect 0 poly2tri - -
  cmp -s stdin.off file.off || fail "IN - differs from IN sq.poly"
  IN=sq.poly expect 0 poly2tri - stdin.1.ele
  expect 0 poly2tri sq.poly file.1.ele
  for f in ele node poly; do cmp -s stdin.1.$f file.1.$f || fail "IN - .$f differs from IN sq.poly"; done
  [[ $(sed -n 2p file.off | cut -d' ' -f2) == $(count file.1.ele) ]] || fail "file.off and file.1.ele differ in triangles"
  expect 3 poly2tri sq.poly cap.off --max-vertices 15
  OUT=cap-stdout.off expect 3 poly2tri sq.poly - --max-vertices 15
  cmp -s cap-stdout.off cap.off || fail "OUT - differs from OUT cap.off on exit 3"
  printf '0 2 0 0\n0 0\n' > novert.poly
  IN=novert.poly expect 1 poly2tri - x.off
  [[ ! -e x.off ]] || fail "x.off written on error"
}

run_cases "$@"
