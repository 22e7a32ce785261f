// Two blocks in one file, each its own physical surface: "upper" = [0, 2] x [1, 2] and
// "lower" = [0, 2] x [0, 1] (not glued: separate points at y = 1), quadrilaterals.
h = 0.25;
Point(1) = {0, 0, 0, h}; Point(2) = {2, 0, 0, h}; Point(3) = {2, 1, 0, h}; Point(4) = {0, 1, 0, h};
Point(5) = {0, 1, 0, h}; Point(6) = {2, 1, 0, h}; Point(7) = {2, 2, 0, h}; Point(8) = {0, 2, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Transfinite Surface {1, 2}; Recombine Surface {1, 2};
Physical Curve("lower_bottom") = {1}; Physical Curve("lower_top") = {3};
Physical Curve("upper_bottom") = {5}; Physical Curve("upper_top") = {7};
Physical Surface("lower") = {1}; Physical Surface("upper") = {2};
