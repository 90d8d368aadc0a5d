// A soil column 1 m x 1 m x 6 m of three layers, each a physical volume
// with its own soil (issue 22): sand 0-2 m, clay 2-3.5 m, fill 3.5-6 m.
// The boxes are fragmented so that the layers share their interfaces.
SetFactory("OpenCASCADE");
DefineConstant[h = 0.25]; // mesh size, m: geoscni sets it to particles.spacing
Box(1) = {0, 0, 0, 1, 1, 2};
Box(2) = {0, 0, 2, 1, 1, 1.5};
Box(3) = {0, 0, 3.5, 1, 1, 2.5};
BooleanFragments{ Volume{1:3}; Delete; }{ }
e = 1e-6;
Physical Surface("xmin") = Surface In BoundingBox{-e, -e, -e, e, 1 + e, 6 + e};
Physical Surface("xmax") = Surface In BoundingBox{1 - e, -e, -e, 1 + e, 1 + e, 6 + e};
Physical Surface("ymin") = Surface In BoundingBox{-e, -e, -e, 1 + e, e, 6 + e};
Physical Surface("ymax") = Surface In BoundingBox{-e, 1 - e, -e, 1 + e, 1 + e, 6 + e};
Physical Surface("bottom") = Surface In BoundingBox{-e, -e, -e, 1 + e, 1 + e, e};
Physical Surface("top") = Surface In BoundingBox{-e, -e, 6 - e, 1 + e, 1 + e, 6 + e};
Physical Volume("sand") = Volume In BoundingBox{-e, -e, -e, 1 + e, 1 + e, 2 + e};
Physical Volume("clay") = Volume In BoundingBox{-e, -e, 2 - e, 1 + e, 1 + e, 3.5 + e};
Physical Volume("fill") = Volume In BoundingBox{-e, -e, 3.5 - e, 1 + e, 1 + e, 6 + e};
MeshSize{PointsOf{Volume{:};}} = h;
