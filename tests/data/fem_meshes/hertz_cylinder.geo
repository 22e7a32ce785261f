// The Hertz quarter cylinder of problems/hertz_cylinder.toml (radius 1, centre (0, 1), right of
// its vertical axis), for the finite element twin of the Hertz case (rigid flat). The arc is
// split 30 degrees from the bottom into the contact edge "arc" and the free "rim"; the
// physical curves carry the TOML twin's edge names. Element size s along the arc, 2.5 s at the
// rim's end and 5 s at the top-left corner (make_meshes.py scales all three).
s = 0.02;
Point(1) = {0, 0, 0, s};
Point(2) = {0.5, 0.1339745962155614, 0, s};
Point(3) = {1, 1, 0, 2.5 * s};
Point(4) = {0, 1, 0, 5 * s};
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
