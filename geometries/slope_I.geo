// Slope I (DESIGN.md, "Slopes from the paper"): a 10 m high 45-degree slope,
// cross-section in x-z (0,0) (20,0) (10,10) (0,10), 10 m wide in y, with a
// footing strip 6 <= x <= 9 on the crest across the whole width.
// The paper's figures with the dimensions are not in its text; these are
// geoscni's definitions. Built-in kernel, every surface named.
DefineConstant[h = 0.3]; // mesh size, m: geoscni sets it to particles.spacing
W = 10; // width in y

// the cross-section at y = 0 and y = W; the crest split at x = 6 and x = 9
For k In {0:1}
  y = k * W;
  Point(10 * k + 1) = {0, y, 0, h};
  Point(10 * k + 2) = {20, y, 0, h};
  Point(10 * k + 3) = {10, y, 10, h};
  Point(10 * k + 4) = {9, y, 10, h};
  Point(10 * k + 5) = {6, y, 10, h};
  Point(10 * k + 6) = {0, y, 10, h};
  For i In {1:6}
    Line(10 * k + i) = {10 * k + i, 10 * k + (i % 6) + 1};
  EndFor
EndFor
For i In {1:6}
  Line(100 + i) = {i, 10 + i}; // across the width
EndFor

Curve Loop(1) = {1, 2, 3, 4, 5, 6};         Plane Surface(1) = {1}; // y = 0
Curve Loop(2) = {11, 12, 13, 14, 15, 16};   Plane Surface(2) = {2}; // y = W
Curve Loop(3) = {1, 102, -11, -101};        Plane Surface(3) = {3}; // bottom
Curve Loop(4) = {2, 103, -12, -102};        Plane Surface(4) = {4}; // face
Curve Loop(5) = {3, 104, -13, -103};        Plane Surface(5) = {5}; // crest 9..10
Curve Loop(6) = {4, 105, -14, -104};        Plane Surface(6) = {6}; // footing
Curve Loop(7) = {5, 106, -15, -105};        Plane Surface(7) = {7}; // crest 0..6
Curve Loop(8) = {6, 101, -16, -106};        Plane Surface(8) = {8}; // back
Surface Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8};
Volume(1) = {1};

Physical Surface("bottom") = {3};
Physical Surface("back") = {8};
Physical Surface("sides") = {1, 2};
Physical Surface("footing") = {6};
Physical Surface("top") = {5, 7};
Physical Surface("face") = {4};
Physical Volume("soil") = {1};
