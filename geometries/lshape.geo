// An L-shaped body (re-entrant edge along y at x = 1, z = 1): the
// cross-section in x-z is [0,2] x [0,1] plus [0,1] x [1,2], 1 m wide in y.
SetFactory("OpenCASCADE");
DefineConstant[h = 0.15]; // mesh size, m: geoscni sets it to particles.spacing
Box(1) = {0, 0, 0, 2, 1, 1};
Box(2) = {0, 0, 1, 1, 1, 1};
BooleanUnion(3) = {Volume{1}; Delete;}{Volume{2}; Delete;};
// name the faces by where they lie
eps = 1e-6;
Physical Surface("bottom") = Surface In BoundingBox{-eps, -eps, -eps, 2 + eps, 1 + eps, eps};
Physical Surface("back") = Surface In BoundingBox{-eps, -eps, -eps, eps, 1 + eps, 2 + eps};
Physical Surface("sides") = {Surface In BoundingBox{-eps, -eps, -eps, 2 + eps, eps, 2 + eps},
                             Surface In BoundingBox{-eps, 1 - eps, -eps, 2 + eps, 1 + eps, 2 + eps}};
Physical Surface("step") = {Surface In BoundingBox{1 - eps, -eps, 1 - eps, 2 + eps, 1 + eps, 1 + eps},
                            Surface In BoundingBox{1 - eps, -eps, 1 - eps, 1 + eps, 1 + eps, 2 + eps}};
Physical Surface("top") = Surface In BoundingBox{-eps, -eps, 2 - eps, 1 + eps, 1 + eps, 2 + eps};
Physical Surface("front") = Surface In BoundingBox{2 - eps, -eps, -eps, 2 + eps, 1 + eps, 1 + eps};
Physical Volume("soil") = {3};
MeshSize{PointsOf{Volume{3};}} = h;
