// The left half of geometries/box.geo (2 m x 1 m x 1 m), cut at x = 1: the
// cut face is the symmetry plane "symmetry" (test_economy_cli.sh).
SetFactory("OpenCASCADE");
DefineConstant[h = 0.2]; // mesh size, m: geoscni sets it to particles.spacing
Box(1) = {0, 0, 0, 1, 1, 1};
Physical Surface("xmin") = {1};
Physical Surface("symmetry") = {2};
Physical Surface("ymin") = {3};
Physical Surface("ymax") = {4};
Physical Surface("bottom") = {5};
Physical Surface("top") = {6};
Physical Volume("soil") = {1};
MeshSize{PointsOf{Volume{1};}} = h;
