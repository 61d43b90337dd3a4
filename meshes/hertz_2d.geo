// Hertz contact in 2D plane strain, half model (x >= 0, symmetry at x = 0): a quarter of a
// cylinder of radius 1 (slave body, centre (0, 1)) on a 4 x 4 block (master body), touching at the
// origin. All-quadrilateral mesh (triangles recombined and subdivided), refined towards the
// contact point; `refine` halves the smallest element size each step.
// Boundaries: 1 slave arc, 2 master (block top), 3 clamped (block bottom), 4 loaded (cylinder
// top, y = 1), 5 symmetry x = 0.
Geometry.AutoCoherence = 0;
DefineConstant[ refine = 1 ];
hmin = 0.04 / refine; hmax = 0.6;
Point(1) = {0, -4, 0}; Point(2) = {4, -4, 0}; Point(3) = {4, 0, 0}; Point(4) = {0, 0, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Point(11) = {0, 0, 0}; Point(12) = {1, 1, 0}; Point(13) = {0, 1, 0};
Circle(11) = {11, 13, 12}; Line(12) = {12, 13}; Line(13) = {13, 11};
Curve Loop(11) = {11, 12, 13}; Plane Surface(11) = {11};
Field[1] = Distance; Field[1].PointsList = {4, 11};
Field[2] = Threshold; Field[2].InField = 1; Field[2].SizeMin = hmin; Field[2].SizeMax = hmax;
Field[2].DistMin = 0.25; Field[2].DistMax = 2.0;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0; Mesh.MeshSizeFromPoints = 0; Mesh.MeshSizeFromCurvature = 0;
Mesh.RecombineAll = 1; Mesh.SubdivisionAlgorithm = 1;
Physical Surface("master_body", 1) = {1};
Physical Surface("slave_body", 2) = {11};
Physical Curve("slave", 1) = {11};
Physical Curve("master", 2) = {3};
Physical Curve("clamped", 3) = {1};
Physical Curve("loaded", 4) = {12};
Physical Curve("symmetry_x", 5) = {4, 13};
