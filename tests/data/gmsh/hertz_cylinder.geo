// The Hertz quarter cylinder of problems/hertz_cylinder.toml and tests/validation/hertz.rs:
// the quarter of the disk of radius 1 about (0, 1) right of its vertical axis; its arc is split
// 30 degrees from the bottom into the contact edge "arc" and the free "rim". The arcs are
// meshed at size h (make_meshes.py sets h = 0.02, 0.01, 0.005, the twin's node spacings).
If (!Exists(h))
  h = 0.01;
EndIf
Point(1) = {0, 0, 0, h};
Point(2) = {0.5, 0.1339745962155614, 0, h};
Point(3) = {1, 1, 0, h};
Point(4) = {0, 1, 0, 0.1};
Circle(1) = {1, 4, 2};
Circle(2) = {2, 4, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("arc") = {1};
Physical Curve("rim") = {2};
Physical Curve("top") = {3};
Physical Curve("axis") = {4};
Physical Surface("cylinder") = {1};
