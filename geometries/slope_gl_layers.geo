// Griffiths & Lane (1999), example 4: a 2:1 slope H = 10 m high of
// undrained clay on a foundation layer of another clay, H thick (depth
// factor D = 2) on a firm base; runout and crest 2 H each (docs/fos.md,
// "Layers"). Two physical volumes, "slope" and "foundation", which the
// case gives their own soils (materials:). A plane-strain section: a slab
// two mesh steps thick in y, held by rollers on its faces.
SetFactory("OpenCASCADE");
DefineConstant[h = 1.0]; // mesh size, m: geoscni sets it to particles.spacing
H = 10;          // slope height
L = 2 * H;       // the slope's run (2:1)
R = 2 * H;       // runout in front of the toe
C = 2 * H;       // crest behind the slope's top edge
DefineConstant[D = 2]; // depth factor: the foundation is (D - 1) H thick
F = (D - 1) * H;
T = 2 * h;       // thickness in y
// the foundation x from -R to L + C, z from -F to 0; the slope on it
Rectangle(1) = {-R, -F, 0, R + L + C, F};
Point(101) = {0, 0, 0, h};
Point(102) = {L + C, 0, 0, h};
Point(103) = {L + C, H, 0, h};
Point(104) = {L, H, 0, h};
Line(101) = {101, 102};
Line(102) = {102, 103};
Line(103) = {103, 104};
Line(104) = {104, 101};
Curve Loop(101) = {101:104};
Plane Surface(2) = {101};
// drawn in x-y, turned into x-z (y the section's thickness)
Rotate {{1, 0, 0}, {0, 0, 0}, Pi / 2} { Surface{1, 2}; }
BooleanFragments{ Surface{1, 2}; Delete; }{ }
Extrude {0, -T, 0} { Surface{:}; }
BooleanFragments{ Volume{:}; Delete; }{ }
e = 1e-6;
X0 = -R; X1 = L + C; Y0 = -T; Z0 = -F;
Physical Surface("bottom") = Surface In BoundingBox{X0 - e, Y0 - e, Z0 - e, X1 + e, e, Z0 + e};
Physical Surface("back") = Surface In BoundingBox{X1 - e, Y0 - e, Z0 - e, X1 + e, e, H + e};
Physical Surface("front") = Surface In BoundingBox{X0 - e, Y0 - e, Z0 - e, X0 + e, e, e};
Physical Surface("sides") = {Surface In BoundingBox{X0 - e, -e, Z0 - e, X1 + e, e, H + e}, Surface In BoundingBox{X0 - e, Y0 - e, Z0 - e, X1 + e, Y0 + e, H + e}};
Physical Surface("crest") = Surface In BoundingBox{L - e, Y0 - e, H - e, X1 + e, e, H + e};
Physical Surface("face") = Surface In BoundingBox{-e, Y0 - e, -e, L + e, e, H + e};
Physical Surface("runout") = Surface In BoundingBox{X0 - e, Y0 - e, -e, e, e, e};
Physical Volume("slope") = Volume In BoundingBox{-e, Y0 - e, -e, X1 + e, e, H + e};
Physical Volume("foundation") = Volume In BoundingBox{X0 - e, Y0 - e, Z0 - e, X1 + e, e, e};
MeshSize{PointsOf{Volume{:};}} = h;
