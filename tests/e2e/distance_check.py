"""distance_check.py MESH F.nrrd E IMPLICIT_EVAL: the README's distance bound,
measured without the mesher's own figure: each triangle's surface centre (a
zero of f on its dual Voronoi edge, which lies on the line through the
triangle's circumcentre along its normal) is within E of its plane. So f
must change sign (or vanish) on that line within E of the circumcentre: f is
sampled by implicit-eval at 17 points from -E to +E along the normal (with
1e-6 E of slack at the ends) and a triangle where f keeps one sign fails.
A passing triangle may still have its centre on another zero further out;
a failing one cannot meet the bound. With --centroids, also |f| at each
triangle's centroid must be at most 2E (the bound's second half). Prints
the triangle count and the worst triangle's smallest |f| on failure."""
import math, os, subprocess, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import surface_read

mesh, fpath, E, evaluate = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
centroids = '--centroids' in sys.argv[5:]
m = surface_read.read(mesh)
P, T = m['points'], m['triangles']
K = 17
sub = lambda a, b: [a[i] - b[i] for i in range(3)]
dot = lambda a, b: sum(a[i] * b[i] for i in range(3))
cross = lambda a, b: [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
lines = []
for t in T:
    a, b, c = (P[i] for i in t)
    ab, ac = sub(b, a), sub(c, a)
    n = cross(ab, ac)
    nn = dot(n, n)
    # Circumcentre: a + ((|ac|^2 (n x ab)) + (|ab|^2 (ac x n))) / (2 |n|^2).
    u, v = cross(n, ab), cross(ac, n)
    cc = [a[i] + (dot(ac, ac) * u[i] + dot(ab, ab) * v[i]) / (2 * nn) for i in range(3)]
    un = [x / math.sqrt(nn) for x in n]
    for k in range(K):
        s = E * (1 + 1e-6) * (2 * k / (K - 1) - 1)
        lines.append('%.17g %.17g %.17g' % tuple(cc[i] + s * un[i] for i in range(3)))
if centroids:
    for t in T:
        lines.append('%.17g %.17g %.17g' % tuple(sum(P[j][i] for j in t) / 3 for i in range(3)))
out = subprocess.run([evaluate, '-q', fpath, '-', '--allow-outside'], input='\n'.join(lines) + '\n',
                     capture_output=True, text=True, check=True).stdout.split()
f = [float(x) for x in out]
assert len(f) == (K + centroids) * len(T), (len(f), (K + centroids) * len(T))
bad = []
for j in range(len(T)):
    s = f[K * j:K * j + K]
    if not (min(s) <= 0 <= max(s)):
        bad.append((min(abs(x) for x in s), j))
print('%d triangles, %d with no zero of f within E = %g of their plane' % (len(T), len(bad), E))
if bad:
    print('worst: triangle %d, smallest |f| %g' % (max(bad)[1], max(bad)[0]))
    sys.exit(1)
if centroids:
    fc = f[K * len(T):]
    worst = max(range(len(T)), key=lambda j: abs(fc[j]))
    print('largest |f| at a centroid: %g (2E = %g), triangle %d' % (abs(fc[worst]), 2 * E, worst))
    if abs(fc[worst]) > 2 * E * (1 + 1e-9):
        sys.exit(1)
