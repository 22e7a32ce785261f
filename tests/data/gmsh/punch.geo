// Obstacle curves only (no surface): the flat punch of problems/flat_punch.toml with sharp
// corners, walked down its left side, along its face and up its right side (the obstacle on
// the left of the walk), as the physical curve "punch"; and a closed circle of radius 0.05
// about (0.5, 0.5) in four arcs, counter-clockwise, as the physical curve "ring". Meshed in
// one dimension at size h (make_meshes.py: h = 0.05; the punch's face in 4 pieces).
If (!Exists(h))
  h = 0.05;
EndIf
Point(1) = {-0.1, 1, 0, h};
Point(2) = {-0.1, 0, 0, h};
Point(3) = {0.1, 0, 0, h};
Point(4) = {0.1, 1, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Physical Curve("punch") = {1, 2, 3};
Point(5) = {0.5, 0.5, 0, h};
Point(6) = {0.55, 0.5, 0, h};
Point(7) = {0.5, 0.55, 0, h};
Point(8) = {0.45, 0.5, 0, h};
Point(9) = {0.5, 0.45, 0, h};
Circle(4) = {6, 5, 7};
Circle(5) = {7, 5, 8};
Circle(6) = {8, 5, 9};
Circle(7) = {9, 5, 6};
Physical Curve("ring") = {4, 5, 6, 7};
