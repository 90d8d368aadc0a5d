// issue 21 reproducer site_coordinates: y shifted by 4,467,890 m and one
// point at x = 512345 (gmsh aborted).
// My slope: 6 m high, 30 degrees, with a 2 m berm at mid-height (z = 3),
// on a 2 m thick foundation layer. Cross-section in x-z, extruded 5 m in y.
DefineConstant[h = 0.5];
X0 = 512345; Y0 = 4467890; Z0 = 231;
W = 5;
s = 3 / Tan(Pi / 6); // horizontal run of each 3 m bench at 30 degrees
xc = 8;              // crest edge
For k In {0:1}
  y = Y0 + k * W;
  Point(20*k + 1)  = {0, y, -2, h};
  Point(20*k + 2)  = {26, y, -2, h};
  Point(20*k + 3)  = {26, y, 0, h};
  Point(20*k + 4)  = {xc + 2*s + 2, y, 0, h};   // toe
  Point(20*k + 5)  = {xc + s + 2, y, 3, h};     // berm outer edge
  Point(20*k + 6)  = {xc + s, y, 3, h};         // berm inner edge
  Point(20*k + 7)  = {xc, y, 6, h};             // crest edge
  Point(20*k + 8)  = {6, y, 6, h};              // footing front edge
  Point(20*k + 9)  = {4, y, 6, h};              // footing back edge
  Point(20*k + 10) = {X0 + 0, y, Z0 + 6, h};
  For i In {1:10}
    Line(20*k + i) = {20*k + i, 20*k + (i % 10) + 1};
  EndFor
EndFor
For i In {1:10}
  Line(100 + i) = {i, 20 + i};
EndFor
Curve Loop(1) = {1:10};         Plane Surface(1) = {1};
Curve Loop(2) = {21:30};        Plane Surface(2) = {2};
For i In {1:10}
  Curve Loop(10 + i) = {i, 100 + (i % 10) + 1, -(20 + i), -(100 + i)};
  Plane Surface(10 + i) = {10 + i};
EndFor
Surface Loop(1) = {1, 2, 11:20};
Volume(1) = {1};

Physical Surface("bottom") = {11};
Physical Surface("front") = {12};
Physical Surface("toe_ground") = {13};
Physical Surface("lower_face") = {14};
Physical Surface("berm") = {15};
Physical Surface("upper_face") = {16};
Physical Surface("crest") = {17, 19};
Physical Surface("footing") = {18};
Physical Surface("back") = {20};
Physical Surface("sides") = {1, 2};
Physical Volume("soil") = {1};
