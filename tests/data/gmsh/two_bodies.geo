// Two blocks in one file, each its own physical surface and every side a physical curve, for
// two [[body]] tables reading the same file (tests/validation/gmsh.rs): "upper" = [0, 2] x [1, 2]
// meshed at 0.2 and "lower" = [0, 2] x [0, 1] at 0.25 (non-matching at y = 1; not glued:
// separate points there), quadrilaterals.
Point(1) = {0, 0, 0, 0.25}; Point(2) = {2, 0, 0, 0.25}; Point(3) = {2, 1, 0, 0.25}; Point(4) = {0, 1, 0, 0.25};
Point(5) = {0, 1, 0, 0.2}; Point(6) = {2, 1, 0, 0.2}; Point(7) = {2, 2, 0, 0.2}; Point(8) = {0, 2, 0, 0.2};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Transfinite Curve {1, 3} = 9; Transfinite Curve {2, 4} = 5;
Transfinite Curve {5, 7} = 11; Transfinite Curve {6, 8} = 6;
Transfinite Surface {1, 2}; Recombine Surface {1, 2};
Physical Curve("lower_bottom") = {1}; Physical Curve("lower_right") = {2};
Physical Curve("lower_top") = {3}; Physical Curve("lower_left") = {4};
Physical Curve("upper_bottom") = {5}; Physical Curve("upper_right") = {6};
Physical Curve("upper_top") = {7}; Physical Curve("upper_left") = {8};
Physical Surface("lower") = {1}; Physical Surface("upper") = {2};
