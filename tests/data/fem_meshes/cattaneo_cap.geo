// The cylinder cap of problems/cattaneo_mindlin.toml (radius 1, centre (0, 1); the part below
// the chord y = 0.4, 1 wide), for the finite element twin of the Cattaneo-Mindlin case. The
// physical curves carry the TOML twin's edge names; `arc` (|x| <= 0.25) may touch. Element
// size s along the arc, 2.5 s at the top chord (make_meshes.py scales both).
s = 0.02;
Point(1) = {0.5, 0.4, 0, 2.5 * s};
Point(2) = {-0.5, 0.4, 0, 2.5 * s};
Point(3) = {-0.5, 0.1339745962155614, 0, 1.5 * s};
Point(4) = {-0.25, 0.031754163448145745, 0, s};
Point(5) = {0.25, 0.031754163448145745, 0, s};
Point(6) = {0.5, 0.1339745962155614, 0, 1.5 * s};
Point(7) = {0, 1, 0, s};
Line(1) = {1, 2};
Line(2) = {2, 3};
Circle(3) = {3, 7, 4};
Circle(4) = {4, 7, 5};
Circle(5) = {5, 7, 6};
Line(6) = {6, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};
Physical Curve("top") = {1};
Physical Curve("left") = {2};
Physical Curve("left_arc") = {3};
Physical Curve("arc") = {4};
Physical Curve("right_arc") = {5};
Physical Curve("right") = {6};
Physical Surface("cylinder") = {1};
