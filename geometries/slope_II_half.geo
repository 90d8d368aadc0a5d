// Half of Slope II (slope_II.geo) cut at its mid-plane y = 6: the same
// cross-section x-z (0,0) (20,0) (10,10) (0,10), 6 m wide in y, with half the
// footing patch, 6 <= x <= 9, 4.5 <= y <= 6, on the crest. The cut face
// y = 6 is the physical surface "symmetry" (boundary entry
// {symmetry: true}, docs/economy.md). Built-in kernel, every surface named.
DefineConstant[h = 0.3]; // mesh size, m: geoscni sets it to particles.spacing
W = 6; // half the width of Slope II

// the cross-section at y = 0
Point(1) = {0, 0, 0, h};
Point(2) = {20, 0, 0, h};
Point(3) = {10, 0, 10, h};
Point(4) = {0, 0, 10, h};
// the cross-section at y = W, its crest split at x = 9 and x = 6
Point(11) = {0, W, 0, h};
Point(12) = {20, W, 0, h};
Point(13) = {10, W, 10, h};
Point(14) = {9, W, 10, h};
Point(15) = {6, W, 10, h};
Point(16) = {0, W, 10, h};
// the footing's corners inside the crest
Point(31) = {6, 4.5, 10, h};
Point(32) = {9, 4.5, 10, h};

For i In {1:4}
  Line(i) = {i, (i % 4) + 1};
EndFor
For i In {1:6}
  Line(10 + i) = {10 + i, 10 + (i % 6) + 1};
EndFor
Line(101) = {1, 11};
Line(102) = {2, 12};
Line(103) = {3, 13};
Line(104) = {4, 16};
Line(31) = {31, 32};
Line(32) = {32, 14};
Line(33) = {15, 31};

Curve Loop(1) = {1, 2, 3, 4};                       Plane Surface(1) = {1}; // y = 0
Curve Loop(2) = {11, 12, 13, 14, 15, 16};           Plane Surface(2) = {2}; // y = W
Curve Loop(3) = {1, 102, -11, -101};                Plane Surface(3) = {3}; // bottom
Curve Loop(4) = {2, 103, -12, -102};                Plane Surface(4) = {4}; // face
Curve Loop(5) = {3, 104, -15, 33, 31, 32, -13, -103}; Plane Surface(5) = {5}; // crest
Curve Loop(6) = {31, 32, 14, 33};                   Plane Surface(6) = {6}; // footing
Curve Loop(8) = {4, 101, -16, -104};                Plane Surface(8) = {8}; // back
Surface Loop(1) = {1, 2, 3, 4, 5, 6, 8};
Volume(1) = {1};

Physical Surface("bottom") = {3};
Physical Surface("back") = {8};
Physical Surface("sides") = {1};
Physical Surface("symmetry") = {2};
Physical Surface("footing") = {6};
Physical Surface("top") = {5};
Physical Surface("face") = {4};
Physical Volume("soil") = {1};
