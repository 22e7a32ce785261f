// The quarter plate of problems/plate_with_hole.toml: [0, 10]^2 outside the hole of radius 1
// centred at the origin. Physical curves carry the edge names of the TOML twin.
// Meshes in this folder: see make_meshes.py (h = 1; problems/plate_with_hole_gmsh.msh: h = 0.4,
// the hole at 0.1, the node spacing of problems/plate_with_hole.toml).
If (!Exists(h))
  h = 1.0;
EndIf
Point(1) = {1, 0, 0, h / 4};
Point(2) = {10, 0, 0, h};
Point(3) = {10, 10, 0, h};
Point(4) = {0, 10, 0, h};
Point(5) = {0, 1, 0, h / 4};
Point(6) = {0, 0, 0, h};
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
