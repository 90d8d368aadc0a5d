// A soil column 1 m x 1 m x 4 m with every face named: the geostatic
// stage's level-ground check (test_geostatic.sh).
SetFactory("OpenCASCADE");
DefineConstant[h = 0.25]; // mesh size, m: geoscni sets it to particles.spacing
Box(1) = {0, 0, 0, 1, 1, 4};
Physical Surface("xmin") = {1};
Physical Surface("xmax") = {2};
Physical Surface("ymin") = {3};
Physical Surface("ymax") = {4};
Physical Surface("bottom") = {5};
Physical Surface("top") = {6};
Physical Volume("soil") = {1};
MeshSize{PointsOf{Volume{1};}} = h;
