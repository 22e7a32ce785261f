// Two elastic spheres of revolution touching at the origin, for the finite element twin of
// tests/validation/axisymmetric_spheres.rs (the MFVM test): the r-z sections (r >= 0) of the
// upper sphere, radius 1 about (0, 1), and of the lower sphere, radius 2 about (0, -2), each a
// quarter disk cut at its equatorial plane. Each arc is split 30 degrees from the contact
// point into the contact edge "<body>_arc" and the free "<body>_rim", as the MFVM twin's
// curves. The two surfaces share no point (separate points at the origin: not glued), so two
// [[body]] tables read the same file (surfaces "upper" and "lower").
// Mesh size: hc within 0.15 of the origin (about twice the contact radius 0.074), growing
// linearly with the distance to H at 1.0 (make_two_spheres.py sets hc and H).
If (!Exists(hc))
  hc = 0.02;
EndIf
If (!Exists(H))
  H = 0.2;
EndIf
// Upper sphere.
Point(1) = {0, 0, 0, hc};
Point(2) = {0.5, 0.1339745962155614, 0, H};
Point(3) = {1, 1, 0, H};
Point(4) = {0, 1, 0, H};
Circle(1) = {1, 4, 2};
Circle(2) = {2, 4, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
// Lower sphere.
Point(5) = {0, -2, 0, H};
Point(6) = {2, -2, 0, H};
Point(7) = {1, -0.2679491924311228, 0, H};
Point(8) = {0, 0, 0, hc};
Line(5) = {5, 6};
Circle(6) = {6, 5, 7};
Circle(7) = {7, 5, 8};
Line(8) = {8, 5};
Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(2) = {2};
Field[1] = Distance;
Field[1].PointsList = {1, 8};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hc;
Field[2].SizeMax = H;
Field[2].DistMin = 0.15;
Field[2].DistMax = 1.0;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Physical Curve("upper_arc") = {1};
Physical Curve("upper_rim") = {2};
Physical Curve("upper_top") = {3};
Physical Curve("upper_axis") = {4};
Physical Curve("lower_bottom") = {5};
Physical Curve("lower_rim") = {6};
Physical Curve("lower_arc") = {7};
Physical Curve("lower_axis") = {8};
Physical Surface("upper") = {1};
Physical Surface("lower") = {2};
