// A block of soil with a square patch on its top pushed down into it, as
// Slope II's footing patch is (tests/solver/test_punch.sh): the soil beside
// the patch's edges is dragged down and crushed within one spacing.
SetFactory("OpenCASCADE");
DefineConstant[h = 0.2]; // mesh size, m: geoscni sets it to particles.spacing
L = 3;   // block length and width, m
D = 1.6; // depth, m
B = 1;   // patch width, m
Box(1) = {0, 0, 0, L, L, D};
Rectangle(100) = {(L - B) / 2, (L - B) / 2, D, B, B};
BooleanFragments{ Volume{1}; Delete; }{ Surface{100}; Delete; }
e = 1e-6;
Physical Surface("bottom") = Surface In BoundingBox{-e, -e, -e, L + e, L + e, e};
Physical Surface("sides") = {Surface In BoundingBox{-e, -e, -e, e, L + e, D + e},
                             Surface In BoundingBox{L - e, -e, -e, L + e, L + e, D + e},
                             Surface In BoundingBox{-e, -e, -e, L + e, e, D + e},
                             Surface In BoundingBox{-e, L - e, -e, L + e, L + e, D + e}};
Physical Surface("punch") = Surface In BoundingBox{(L - B) / 2 - e, (L - B) / 2 - e, D - e, (L + B) / 2 + e, (L + B) / 2 + e, D + e};
Physical Volume("soil") = {1};
