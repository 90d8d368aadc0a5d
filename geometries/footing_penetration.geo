// A rigid strip footing pushed deep into a layer of clay, in plane strain
// (issue 15, point 6): half of the problem of Kardani et al. (2015), cut at
// the footing's centre line x = 0. The footing is the strip 0 <= x <= B/2 on
// the top z = D (width B = 1 m); the soil reaches x = 5 B and depth D = 5 B.
// The slab is two mesh steps thick in y; rollers on its two y faces make the
// problem plane strain.
DefineConstant[h = 0.1]; // mesh size, m: geoscni sets it to particles.spacing
B = 1.0;     // footing width, m
W = 5 * B;   // half-width of the soil
D = 5 * B;   // depth of the soil
T = 2 * h;   // thickness in y

For k In {0:1}
  y = k * T;
  Point(10 * k + 1) = {0, y, 0, h};
  Point(10 * k + 2) = {W, y, 0, h};
  Point(10 * k + 3) = {W, y, D, h};
  Point(10 * k + 4) = {B / 2, y, D, h};
  Point(10 * k + 5) = {0, y, D, h};
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
Curve Loop(4) = {2, 103, -12, -102};      Plane Surface(4) = {4}; // x = W
Curve Loop(5) = {3, 104, -13, -103};      Plane Surface(5) = {5}; // top, x > B/2
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
