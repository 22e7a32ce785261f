// The Kirsch quarter plate of tests/validation/kirsch.rs: [0, 5]^2 outside the hole of radius
// 1 centred at the origin, the hole meshed at size h (make_meshes.py sets h = 0.2, 0.1, 0.05,
// the twin's node spacings); the straight edges' sizes do not matter to a body whose nodes
// are laid out inside the boundary. Physical curves carry the edge names of the twin.
If (!Exists(h))
  h = 0.1;
EndIf
Point(1) = {1, 0, 0, h};
Point(2) = {5, 0, 0, 1};
Point(3) = {5, 5, 0, 1};
Point(4) = {0, 5, 0, 1};
Point(5) = {0, 1, 0, h};
Point(6) = {0, 0, 0, 1};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Circle(5) = {5, 6, 1};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
Physical Curve("hole") = {5};
Physical Surface("plate") = {1};
