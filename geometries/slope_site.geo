// A layered, wet slope in plane strain (issue 22, point 5; README "Layers
// and water"): a sand embankment 8 m high at 2:1 on a clay layer 6 m thick
// over rock. The runout in front of the toe and the crest behind it 16 m
// each; a strip footing 2 m wide on the crest, 2 m behind its edge. Three
// physical volumes, "sand", "clay" and "rock", which the case gives their
// own soils; the case's water table runs through the clay and the sand.
// A slab two mesh steps thick in y, held by rollers on its faces.
SetFactory("OpenCASCADE");
DefineConstant[h = 0.5]; // mesh size, m: geoscni sets it to particles.spacing
H = 8;           // embankment height
L = 2 * H;       // its run (2:1)
R = 16;          // runout in front of the toe
C = 16;          // crest behind the top edge
Dc = 6;          // clay thickness
Dr = 4;          // rock above the base
F0 = L + 2;      // the footing's edges
F1 = L + 4;
T = 2 * h;       // thickness in y
X0 = -R; X1 = L + C;
Rectangle(1) = {X0, -Dc - Dr, 0, X1 - X0, Dr};  // rock
Rectangle(2) = {X0, -Dc, 0, X1 - X0, Dc};       // clay
Point(101) = {0, 0, 0, h};
Point(102) = {X1, 0, 0, h};
Point(103) = {X1, H, 0, h};
Point(104) = {F1, H, 0, h};
Point(105) = {F0, H, 0, h};
Point(106) = {L, H, 0, h};
For i In {0:5}
  Line(101 + i) = {101 + i, 101 + (i + 1) % 6};
EndFor
Curve Loop(101) = {101:106};
Plane Surface(3) = {101};                         // sand
// drawn in x-y, turned into x-z (y the slab's thickness)
Rotate {{1, 0, 0}, {0, 0, 0}, Pi / 2} { Surface{1:3}; }
BooleanFragments{ Surface{1:3}; Delete; }{ }
Extrude {0, -T, 0} { Surface{:}; }
BooleanFragments{ Volume{:}; Delete; }{ }
e = 1e-6;
Y0 = -T; Z0 = -Dc - Dr;
Physical Surface("bottom") = Surface In BoundingBox{X0 - e, Y0 - e, Z0 - e, X1 + e, e, Z0 + e};
Physical Surface("back") = Surface In BoundingBox{X1 - e, Y0 - e, Z0 - e, X1 + e, e, H + e};
Physical Surface("front") = Surface In BoundingBox{X0 - e, Y0 - e, Z0 - e, X0 + e, e, e};
Physical Surface("sides") = {Surface In BoundingBox{X0 - e, -e, Z0 - e, X1 + e, e, H + e}, Surface In BoundingBox{X0 - e, Y0 - e, Z0 - e, X1 + e, Y0 + e, H + e}};
Physical Surface("footing") = Surface In BoundingBox{F0 - e, Y0 - e, H - e, F1 + e, e, H + e};
Physical Surface("crest") = {Surface In BoundingBox{L - e, Y0 - e, H - e, F0 + e, e, H + e}, Surface In BoundingBox{F1 - e, Y0 - e, H - e, X1 + e, e, H + e}};
Physical Surface("face") = Surface In BoundingBox{-e, Y0 - e, -e, L + e, e, H + e};
Physical Surface("runout") = Surface In BoundingBox{X0 - e, Y0 - e, -e, e, e, e};
Physical Volume("sand") = Volume In BoundingBox{-e, Y0 - e, -e, X1 + e, e, H + e};
Physical Volume("clay") = Volume In BoundingBox{X0 - e, Y0 - e, -Dc - e, X1 + e, e, e};
Physical Volume("rock") = Volume In BoundingBox{X0 - e, Y0 - e, Z0 - e, X1 + e, e, -Dc + e};
MeshSize{PointsOf{Volume{:};}} = h;
