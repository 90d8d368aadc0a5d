// A unit box for the post tests' case file: post never meshes it, the case
// reader only checks that the geometry file exists.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 4, 1.5, 1.6};
Physical Surface("bottom") = {5};
Physical Surface("footing") = {6};
Physical Volume("soil") = {1};
