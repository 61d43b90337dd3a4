// Contact patch test, 2D: two 1.0 x 0.5 blocks stacked (lower: master, upper: slave) with
// non-matching meshes (4 vs 5 elements per row times `refine`, upper mesh also with 3 rows).
// A uniform pressure on the top, rollers on x = 0 and on the bottom: the exact solution is a
// homogeneous state and the contact pressure equals the transmitted traction.
// Boundaries: 1 slave, 2 master, 4 loaded (top), 5 symmetry x = 0 (both blocks), 6 bottom.
Geometry.AutoCoherence = 0; // keep coincident points of the two bodies apart
DefineConstant[ refine = 1 ];
Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 0.5, 0}; Point(4) = {0, 0.5, 0};
Point(5) = {0, 0.5, 0}; Point(6) = {1, 0.5, 0}; Point(7) = {1, 1, 0}; Point(8) = {0, 1, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Transfinite Curve{1, 3} = 4 * refine + 1; Transfinite Curve{2, 4} = 2 * refine + 1;
Transfinite Curve{5, 7} = 5 * refine + 1; Transfinite Curve{6, 8} = 3 * refine + 1;
Transfinite Surface{1, 2}; Recombine Surface{1, 2};
Physical Surface("master_body", 1) = {1};
Physical Surface("slave_body", 2) = {2};
Physical Curve("slave", 1) = {5};
Physical Curve("master", 2) = {3};
Physical Curve("loaded", 4) = {7};
Physical Curve("symmetry_x", 5) = {4, 8};
Physical Curve("bottom", 6) = {1};
