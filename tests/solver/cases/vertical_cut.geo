// A vertical cut 10 m high in undrained clay on a firm base at its toe,
// the ground 20 m deep behind it, in plane strain (a slab two mesh steps
// thick in y): the critical height H_c = N c / gamma, N between 3.77 and
// 3.83 (lower and upper bounds; REFERENCES.md), for test_fos.sh.
SetFactory("OpenCASCADE");
DefineConstant[h = 0.5]; // mesh size, m: geoscni sets it to particles.spacing
Box(1) = {0, 0, 0, 20, 2 * h, 10};
Physical Surface("face") = {1};
Physical Surface("back") = {2};
Physical Surface("sides") = {3, 4};
Physical Surface("bottom") = {5};
Physical Surface("top") = {6};
Physical Volume("soil") = {1};
MeshSize{PointsOf{Volume{1};}} = h;
