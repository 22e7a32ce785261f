// The full Kirsch plate of tests/validation/holes.rs: [-5, 5]^2 outside the hole of radius 1
// centred at the origin, the hole a second curve loop (four quarter circles, one physical
// curve "hole"). The hole is meshed at size h (make_meshes.py sets h = 0.2, 0.1, 0.05, the
// twin's node spacings), the corners at size H (default 1; the straight edges' sizes do not
// matter to a body whose nodes are laid out inside the boundary, but they do to the FE path
// on the mesh's own elements).
If (!Exists(h))
  h = 0.1;
EndIf
If (!Exists(H))
  H = 1;
EndIf
Point(1) = {-5, -5, 0, H};
Point(2) = {5, -5, 0, H};
Point(3) = {5, 5, 0, H};
Point(4) = {-5, 5, 0, H};
Point(5) = {0, 0, 0, 1};
Point(6) = {1, 0, 0, h};
Point(7) = {0, 1, 0, h};
Point(8) = {-1, 0, 0, h};
Point(9) = {0, -1, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Circle(5) = {6, 5, 7};
Circle(6) = {7, 5, 8};
Circle(7) = {8, 5, 9};
Circle(8) = {9, 5, 6};
Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(1) = {1, 2};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
Physical Curve("hole") = {5, 6, 7, 8};
Physical Surface("plate") = {1};
