// A rigid strip footing on a layer of soil, in plane strain (issue 7): half
// of the problem, cut at the footing's centre line x = 0. The footing is the
// strip 0 <= x <= 1 (half-width b = 1 m, width B = 2 m) on the top z = 3;
// the soil reaches x = 5 and depth 3 (2.5 B and 1.5 B: beyond the Prandtl
// mechanism, which for phi = 8.6 degrees reaches about x = 3.4 b, depth
// 1.7 b). The slab is two mesh steps thick in y; rollers on its two y faces
// make the problem plane strain.
DefineConstant[h = 0.2]; // mesh size, m: geoscni sets it to particles.spacing
T = 2 * h; // thickness in y

For k In {0:1}
  y = k * T;
  Point(10 * k + 1) = {0, y, 0, h};
  Point(10 * k + 2) = {5, y, 0, h};
  Point(10 * k + 3) = {5, y, 3, h};
  Point(10 * k + 4) = {1, y, 3, h};
  Point(10 * k + 5) = {0, y, 3, h};
  For i In {1:5}
    Line(10 * k + i) = {10 * k + i, 10 * k + (i % 5) + 1};
  EndFor
EndFor
For i In {1:5}
  Line(100 + i) = {i, 10 + i}; // across the thickness
EndFor

Curve Loop(1) = {1, 2, 3, 4, 5};          Plane Surface(1) = {1}; // y = 0
Curve Loop(2) = {11, 12, 13, 14, 15};     Plane Surface(2) = {2}; // y = T
Curve Loop(3) = {1, 102, -11, -101};      Plane Surface(3) = {3}; // bottom
Curve Loop(4) = {2, 103, -12, -102};      Plane Surface(4) = {4}; // x = 5
Curve Loop(5) = {3, 104, -13, -103};      Plane Surface(5) = {5}; // top, x > 1
Curve Loop(6) = {4, 105, -14, -104};      Plane Surface(6) = {6}; // footing
Curve Loop(7) = {5, 101, -15, -105};      Plane Surface(7) = {7}; // x = 0
Surface Loop(1) = {1, 2, 3, 4, 5, 6, 7};
Volume(1) = {1};

Physical Surface("bottom") = {3};
Physical Surface("far") = {4};
Physical Surface("symmetry") = {7};
Physical Surface("sides") = {1, 2};
Physical Surface("footing") = {6};
Physical Surface("top") = {5};
Physical Volume("soil") = {1};
