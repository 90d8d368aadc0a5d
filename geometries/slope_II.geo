// Slope II (DESIGN.md, "Slopes from the paper"): the cross-section of
// Slope I, x-z (0,0) (20,0) (10,10) (0,10), 12 m wide in y, with a square
// footing patch 6 <= x <= 9, 4.5 <= y <= 7.5 on the crest.
// The paper's figures with the dimensions are not in its text; these are
// geoscni's definitions. Built-in kernel, every surface named.
DefineConstant[h = 0.3]; // mesh size, m: geoscni sets it to particles.spacing
W = 12; // width in y

For k In {0:1}
  y = k * W;
  Point(10 * k + 1) = {0, y, 0, h};
  Point(10 * k + 2) = {20, y, 0, h};
  Point(10 * k + 3) = {10, y, 10, h};
  Point(10 * k + 4) = {0, y, 10, h};
  For i In {1:4}
    Line(10 * k + i) = {10 * k + i, 10 * k + (i % 4) + 1};
  EndFor
EndFor
For i In {1:4}
  Line(100 + i) = {i, 10 + i}; // across the width
EndFor
// the footing patch on the crest z = 10
Point(31) = {6, 4.5, 10, h};
Point(32) = {9, 4.5, 10, h};
Point(33) = {9, 7.5, 10, h};
Point(34) = {6, 7.5, 10, h};
Line(31) = {31, 32};
Line(32) = {32, 33};
Line(33) = {33, 34};
Line(34) = {34, 31};

Curve Loop(1) = {1, 2, 3, 4};          Plane Surface(1) = {1}; // y = 0
Curve Loop(2) = {11, 12, 13, 14};      Plane Surface(2) = {2}; // y = W
Curve Loop(3) = {1, 102, -11, -101};   Plane Surface(3) = {3}; // bottom
Curve Loop(4) = {2, 103, -12, -102};   Plane Surface(4) = {4}; // face
Curve Loop(5) = {3, 104, -13, -103};   // crest outline
Curve Loop(6) = {31, 32, 33, 34};      // footing outline
Plane Surface(5) = {5, 6};                                     // crest
Plane Surface(6) = {6};                                        // footing
Curve Loop(8) = {4, 101, -14, -104};   Plane Surface(8) = {8}; // back
Surface Loop(1) = {1, 2, 3, 4, 5, 6, 8};
Volume(1) = {1};

Physical Surface("bottom") = {3};
Physical Surface("back") = {8};
Physical Surface("sides") = {1, 2};
Physical Surface("footing") = {6};
Physical Surface("top") = {5};
Physical Surface("face") = {4};
Physical Volume("soil") = {1};
