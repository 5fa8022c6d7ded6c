// A plate with three holes (two round, one a quadrilateral): Gmsh makes its triangles (tests/e2e/tri2quad.sh, scripts/bench.d/quadsmooth.sh).
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 10, 6};
Disk(2) = {2.5, 3, 0, 1.2}; Disk(3) = {6.2, 4.2, 0, 0.7};
Point(20) = {5.5, 1, 0}; Point(21) = {8.6, 0.8, 0}; Point(22) = {8, 2.6, 0}; Point(23) = {6.8, 2, 0};
Line(20) = {20, 21}; Line(21) = {21, 22}; Line(22) = {22, 23}; Line(23) = {23, 20};
Curve Loop(20) = {20, 21, 22, 23}; Plane Surface(4) = {20};
BooleanDifference(10) = { Surface{1}; Delete; }{ Surface{2, 3, 4}; Delete; };
Physical Surface(1) = {10};
