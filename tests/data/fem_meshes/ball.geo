// The steel ball of problems/ball_impact_axisymmetric.toml for the finite element twin
// (problems/ball_impact_axisymmetric_fem.toml, tests/validation/dynamics.rs): the r-z section
// (r >= 0) of the sphere of radius R = 10 mm about (0, R), a half disk. Its arc is split as the
// MFVM file's curves: "contact" (the lower 30 degrees from the south pole, which touches the
// flat), "rim" (to the equator), "cap" (to the north pole); "axis" is the section's edge on
// r = 0 (split at the centre so that the centre is a mesh vertex). SI units (metres).
// Mesh size: hc within 1 mm of the south pole (about twice the contact radius 0.42 mm),
// growing linearly with the distance to H at 5 mm (make_ball.py sets hc and H).
If (!Exists(hc))
  hc = 1e-4;
EndIf
If (!Exists(H))
  H = 1e-3;
EndIf
R = 0.01;
Point(1) = {0, 0, 0, hc};
Point(2) = {R * Sin(Pi / 6), R - R * Cos(Pi / 6), 0, H};
Point(3) = {R, R, 0, H};
Point(4) = {0, 2 * R, 0, H};
Point(5) = {0, R, 0, H};
Circle(1) = {1, 5, 2};
Circle(2) = {2, 5, 3};
Circle(3) = {3, 5, 4};
Line(4) = {4, 5};
Line(5) = {5, 1};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Field[1] = Distance;
Field[1].PointsList = {1};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hc;
Field[2].SizeMax = H;
Field[2].DistMin = 0.001;
Field[2].DistMax = 0.005;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Physical Curve("contact") = {1};
Physical Curve("rim") = {2};
Physical Curve("cap") = {3};
Physical Curve("axis") = {4, 5};
Physical Surface("ball") = {1};
