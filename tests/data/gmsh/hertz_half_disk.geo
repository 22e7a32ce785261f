// A graded half-disk for the default discretisation (tests/validation/graded_half_disk.rs): the
// lower half of the disk of radius 1 about (0, 1), its flat top y = 1 ("top"), its arc split
// at 20 degrees either side of the bottom into the contact edge "arc" and the free "rim_left",
// "rim_right". The mesh size is hc within 0.15 of the bottom point and grows linearly with
// the distance to H at 0.6 (make_meshes.py sets hc = 0.006, H = 0.08).
If (!Exists(hc))
  hc = 0.006;
EndIf
If (!Exists(H))
  H = 0.08;
EndIf
s = Sin(20 * Pi / 180);
c = Cos(20 * Pi / 180);
Point(1) = {0, 1, 0, H};
Point(2) = {-s, 1 - c, 0, hc};
Point(3) = {s, 1 - c, 0, hc};
Point(4) = {1, 1, 0, H};
Point(5) = {-1, 1, 0, H};
Point(6) = {0, 0, 0, hc};
Circle(1) = {2, 1, 6};
Circle(2) = {6, 1, 3};
Circle(3) = {3, 1, 4};
Line(4) = {4, 5};
Circle(5) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Field[1] = Distance;
Field[1].PointsList = {6};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hc;
Field[2].SizeMax = H;
Field[2].DistMin = 0.15;
Field[2].DistMax = 0.6;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Physical Curve("arc") = {1, 2};
Physical Curve("rim_right") = {3};
Physical Curve("top") = {4};
Physical Curve("rim_left") = {5};
Physical Surface("half_disk") = {1};
