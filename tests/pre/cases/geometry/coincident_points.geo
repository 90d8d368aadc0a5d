// A 1 m cube (built-in kernel) whose top face is drawn with points and
// lines of its own (9 to 12, 13 to 16) where the side faces' top corners
// and edges already are.
DefineConstant[h = 0.25];
Point(1) = {0, 0, 0, h}; Point(2) = {1, 0, 0, h};
Point(3) = {1, 1, 0, h}; Point(4) = {0, 1, 0, h};
Point(5) = {0, 0, 1, h}; Point(6) = {1, 0, 1, h};
Point(7) = {1, 1, 1, h}; Point(8) = {0, 1, 1, h};
Point(9) = {0, 0, 1, h}; Point(10) = {1, 0, 1, h};
Point(11) = {1, 1, 1, h}; Point(12) = {0, 1, 1, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Line(9) = {1, 5}; Line(10) = {2, 6}; Line(11) = {3, 7}; Line(12) = {4, 8};
Line(13) = {9, 10}; Line(14) = {10, 11}; Line(15) = {11, 12};
Line(16) = {12, 9};
Curve Loop(1) = {1, 2, 3, 4};      Plane Surface(1) = {1};
Curve Loop(2) = {1, 10, -5, -9};   Plane Surface(2) = {2};
Curve Loop(3) = {2, 11, -6, -10};  Plane Surface(3) = {3};
Curve Loop(4) = {3, 12, -7, -11};  Plane Surface(4) = {4};
Curve Loop(5) = {4, 9, -8, -12};   Plane Surface(5) = {5};
Curve Loop(6) = {13, 14, 15, 16};  Plane Surface(6) = {6};
Surface Loop(1) = {1, 2, 3, 4, 5, 6};
Volume(1) = {1};
Physical Surface("bottom") = {1};
