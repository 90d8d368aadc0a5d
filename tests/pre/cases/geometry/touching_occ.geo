// Two boxes (OpenCASCADE kernel) stacked without BooleanFragments: the
// upper one sits on the lower one without sharing the face.
SetFactory("OpenCASCADE");
DefineConstant[h = 0.25];
Box(1) = {0, 0, 0, 2, 1, 0.5};
Box(2) = {0.5, 0, 0.5, 1, 1, 0.5};
Physical Surface("bottom") = {5};
MeshSize{PointsOf{Volume{1, 2};}} = h;
