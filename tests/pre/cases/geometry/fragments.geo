// Two boxes (OpenCASCADE kernel) stacked and fragmented: they share the
// face between them (a negative control of the touching check).
SetFactory("OpenCASCADE");
DefineConstant[h = 0.25];
Box(1) = {0, 0, 0, 2, 1, 0.5};
Box(2) = {0.5, 0, 0.5, 1, 1, 0.5};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Physical Surface("bottom") = Surface In BoundingBox{-1e-6, -1e-6, -1e-6, 2 + 1e-6, 1 + 1e-6, 1e-6};
MeshSize{PointsOf{Volume{:};}} = h;
