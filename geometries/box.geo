// A 2 m x 1 m x 1 m box with every face named, for tests.
SetFactory("OpenCASCADE");
DefineConstant[h = 0.2]; // mesh size, m: geoscni sets it to particles.spacing
Box(1) = {0, 0, 0, 2, 1, 1};
Physical Surface("xmin") = {1};
Physical Surface("xmax") = {2};
Physical Surface("ymin") = {3};
Physical Surface("ymax") = {4};
Physical Surface("bottom") = {5};
Physical Surface("top") = {6};
Physical Volume("soil") = {1};
MeshSize{PointsOf{Volume{1};}} = h;
