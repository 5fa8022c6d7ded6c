// A square with a curved inclusion, two regions whose interface is a constraint (tests/e2e/tri2quad.sh, scripts/bench.d/quadsmooth.sh).
Point(1) = {0, 0, 0}; Point(2) = {8, 0, 0}; Point(3) = {8, 8, 0}; Point(4) = {0, 8, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Point(10) = {2, 2, 0}; Point(11) = {6, 2.5, 0}; Point(12) = {5.5, 6, 0}; Point(13) = {2.5, 5.5, 0};
Spline(10) = {10, 11, 12, 13, 10};
Curve Loop(1) = {1, 2, 3, 4}; Curve Loop(2) = {10};
Plane Surface(1) = {1, 2}; Plane Surface(2) = {2};
Physical Surface(1) = {1}; Physical Surface(2) = {2};
