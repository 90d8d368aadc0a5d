// A 1 m cube with named faces, for the case-file tests.
SetFactory("OpenCASCADE");
DefineConstant[h = 0.25];
Box(1) = {0, 0, 0, 1, 1, 1};
Physical Surface("bottom") = {5};
Physical Surface("top") = {6};
Physical Surface("sides") = {1, 2, 3, 4};
Physical Volume("soil") = {1};
Mesh.MeshSizeMax = h;
