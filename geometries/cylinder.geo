// A vertical cylinder of radius 1 m and height 2 m (curved boundary), for
// tests: the mesh's faceted surface is the body the cells fill.
SetFactory("OpenCASCADE");
DefineConstant[h = 0.2]; // mesh size, m: geoscni sets it to particles.spacing
Cylinder(1) = {0, 0, 0, 0, 0, 2, 1};
Physical Surface("mantle") = {1};
Physical Surface("top") = {2};
Physical Surface("bottom") = {3};
Physical Volume("soil") = {1};
MeshSize{PointsOf{Volume{1};}} = h;
