// Two 1 m cubes side by side (built-in kernel), the second shifted by
// 0.5 m in y: their faces at x = 1 overlap in part, and the cubes touch
// there without sharing a face.
DefineConstant[h = 0.25];
For k In {0:1}
  x = k * 1.0;
  y = k * 0.5;
  p = 100 * k;
  Point(p + 1) = {x, y, 0, h}; Point(p + 2) = {x + 1, y, 0, h};
  Point(p + 3) = {x + 1, y + 1, 0, h}; Point(p + 4) = {x, y + 1, 0, h};
  Line(p + 1) = {p + 1, p + 2}; Line(p + 2) = {p + 2, p + 3};
  Line(p + 3) = {p + 3, p + 4}; Line(p + 4) = {p + 4, p + 1};
  Curve Loop(p + 1) = {p + 1, p + 2, p + 3, p + 4};
  Plane Surface(p + 1) = {p + 1};
  out[] = Extrude {0, 0, 1} { Surface{p + 1}; };
  bottoms[k] = p + 1;
EndFor
Physical Surface("bottom") = {bottoms[]};
