// A cross-section whose outline crosses itself (a bow tie), extruded:
// gmsh's surface mesher throws inside an OpenMP region, which no check
// before meshing catches.
DefineConstant[h = 0.5];
Point(1) = {0, 0, 0, h}; Point(2) = {4, 0, 4, h};
Point(3) = {4, 0, 0, h}; Point(4) = {0, 0, 4, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
out[] = Extrude {0, 2, 0} { Surface{1}; };
Physical Surface("bottom") = {1};
