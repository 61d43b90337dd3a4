// Frictionless impact in 2D plane strain, half model (x >= 0, symmetry at x = 0): a half
// cylinder of radius 0.5 (slave body; the quarter disc x >= 0 below its centre (0, 0.5 + gap))
// flies onto a 1.0 x 0.5 block (master body, clamped at its bottom) across an initial gap of
// 0.01. All-quadrilateral mesh (triangles recombined and subdivided), element size 0.05/refine
// (0.025/refine near the contact point).
// Boundaries: 1 slave arc, 2 master (block top), 3 clamped (block bottom), 4 cylinder top
// (free), 5 symmetry x = 0.
Geometry.AutoCoherence = 0;
DefineConstant[ refine = 1 ];
gap = 0.01; R = 0.5;
h = 0.1 / refine; hc = 0.05 / refine;
Point(1) = {0, -0.5, 0, h}; Point(2) = {1, -0.5, 0, h}; Point(3) = {1, 0, 0, h}; Point(4) = {0, 0, 0, hc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Point(11) = {0, gap, 0, hc}; Point(12) = {R, R + gap, 0, h}; Point(13) = {0, R + gap, 0, h};
Circle(11) = {11, 13, 12}; Line(12) = {12, 13}; Line(13) = {13, 11};
Curve Loop(11) = {11, 12, 13}; Plane Surface(11) = {11};
Mesh.RecombineAll = 1; Mesh.SubdivisionAlgorithm = 1;
Physical Surface("master_body", 1) = {1};
Physical Surface("slave_body", 2) = {11};
Physical Curve("slave", 1) = {11};
Physical Curve("master", 2) = {3};
Physical Curve("clamped", 3) = {1};
Physical Curve("top", 4) = {12};
Physical Curve("symmetry_x", 5) = {4, 13};
