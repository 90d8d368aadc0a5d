// A slab of soft clay squeezed sideways against a rigid footing on its top
// (tests/solver/test_rigid.sh): the face x = L moves towards the footing,
// the soil beside the footing rises and is pushed over its edge.
DefineConstant[h = 0.1]; // mesh size, m: geoscni sets it to particles.spacing
L = 2;     // length, m
D = 1;     // depth, m
B = 0.5;   // footing half-width, m (the footing is 0 <= x <= B)
T = 2 * h; // thickness in y
For k In {0:1}
  y = k * T;
  Point(10 * k + 1) = {0, y, 0, h};
  Point(10 * k + 2) = {L, y, 0, h};
  Point(10 * k + 3) = {L, y, D, h};
  Point(10 * k + 4) = {B, y, D, h};
  Point(10 * k + 5) = {0, y, D, h};
  For i In {1:5}
    Line(10 * k + i) = {10 * k + i, 10 * k + (i % 5) + 1};
  EndFor
EndFor
For i In {1:5}
  Line(100 + i) = {i, 10 + i};
EndFor
Curve Loop(1) = {1, 2, 3, 4, 5};      Plane Surface(1) = {1};
Curve Loop(2) = {11, 12, 13, 14, 15}; Plane Surface(2) = {2};
Curve Loop(3) = {1, 102, -11, -101};  Plane Surface(3) = {3};
Curve Loop(4) = {2, 103, -12, -102};  Plane Surface(4) = {4};
Curve Loop(5) = {3, 104, -13, -103};  Plane Surface(5) = {5};
Curve Loop(6) = {4, 105, -14, -104};  Plane Surface(6) = {6};
Curve Loop(7) = {5, 101, -15, -105};  Plane Surface(7) = {7};
Surface Loop(1) = {1, 2, 3, 4, 5, 6, 7};
Volume(1) = {1};
Physical Surface("bottom") = {3};
Physical Surface("pusher") = {4};
Physical Surface("top") = {5};
Physical Surface("footing") = {6};
Physical Surface("symmetry") = {7};
Physical Surface("sides") = {1, 2};
Physical Volume("soil") = {1};
