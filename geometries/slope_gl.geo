// A homogeneous 2:1 slope 10 m high on a firm base at the toe (depth
// factor D = 1), the crest 12 m wide behind it: Griffiths & Lane (1999),
// example 1 (docs/fos.md). A plane-strain section: a slab two mesh steps
// thick in y, held by rollers on its faces (and plane_strain: y). A strip
// footing 2 m wide on the crest, 1 m behind its edge, for a loading stage.
SetFactory("OpenCASCADE");
DefineConstant[h = 0.5]; // mesh size, m: geoscni sets it to particles.spacing
H = 10;           // height
DefineConstant[L = 2 * H]; // the slope's horizontal run (2:1); a file that
                           // sets L first and includes this one draws
                           // another angle (tests/solver/cases/slope_60.geo)
C = 12;           // crest behind the slope's top edge
F0 = L + 1;       // the footing's edges
F1 = L + 3;
T = 2 * h;        // thickness in y
Point(1) = {0, 0, 0, h};
Point(2) = {L + C, 0, 0, h};
Point(3) = {L + C, 0, H, h};
Point(4) = {F1, 0, H, h};
Point(5) = {F0, 0, H, h};
Point(6) = {L, 0, H, h};
For i In {1:6}
  Line(i) = {i, (i % 6) + 1};
EndFor
Curve Loop(1) = {1:6};
Plane Surface(1) = {1};
Extrude {0, T, 0} { Surface{1}; }
e = 1e-6;
Physical Surface("bottom") = Surface In BoundingBox{-e, -e, -e, L + C + e, T + e, e};
Physical Surface("back") = Surface In BoundingBox{L + C - e, -e, -e, L + C + e, T + e, H + e};
Physical Surface("footing") = Surface In BoundingBox{F0 - e, -e, H - e, F1 + e, T + e, H + e};
Physical Surface("crest") = {Surface In BoundingBox{L - e, -e, H - e, F0 + e, T + e, H + e}, Surface In BoundingBox{F1 - e, -e, H - e, L + C + e, T + e, H + e}};
Physical Surface("sides") = {Surface In BoundingBox{-e, -e, -e, L + C + e, e, H + e}, Surface In BoundingBox{-e, T - e, -e, L + C + e, T + e, H + e}};
Physical Surface("face") = Surface In BoundingBox{-e, -e, -e, L + e, T + e, H + e};
Physical Volume("soil") = {1};
MeshSize{PointsOf{Volume{1};}} = h;
