// Contact patch test, 3D: two 1 x 1 x 0.5 blocks stacked (lower: master, upper: slave), with
// non-matching hexahedral meshes (4 vs 5 elements per edge times `refine`). Uniform pressure on
// the top, rollers on x = 0, y = 0 and the bottom: homogeneous exact solution.
// Boundaries: 1 slave, 2 master, 4 loaded (top), 5 symmetry x = 0, 6 symmetry y = 0, 7 bottom.
Geometry.AutoCoherence = 0; // keep coincident points of the two bodies apart
DefineConstant[ refine = 1 ];
Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 1, 0}; Point(4) = {0, 1, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = 4 * refine + 1; Transfinite Surface{1}; Recombine Surface{1};
lower[] = Extrude {0, 0, 0.5} { Surface{1}; Layers{2 * refine}; Recombine; };
Point(101) = {0, 0, 0.5}; Point(102) = {1, 0, 0.5}; Point(103) = {1, 1, 0.5}; Point(104) = {0, 1, 0.5};
Line(101) = {101, 102}; Line(102) = {102, 103}; Line(103) = {103, 104}; Line(104) = {104, 101};
Curve Loop(101) = {101, 102, 103, 104}; Plane Surface(101) = {101};
Transfinite Curve{101, 102, 103, 104} = 5 * refine + 1; Transfinite Surface{101}; Recombine Surface{101};
upper[] = Extrude {0, 0, 0.5} { Surface{101}; Layers{3 * refine}; Recombine; };
Physical Volume("master_body", 1) = {lower[1]};
Physical Volume("slave_body", 2) = {upper[1]};
Physical Surface("slave", 1) = {101};
Physical Surface("master", 2) = {lower[0]};
Physical Surface("loaded", 4) = {upper[0]};
// Extrude returns [top, volume, side1 (from line 1), side2, side3, side4]:
// line 1/101 lies on y = 0, line 4/104 on x = 0.
Physical Surface("symmetry_x", 5) = {lower[5], upper[5]};
Physical Surface("symmetry_y", 6) = {lower[2], upper[2]};
Physical Surface("bottom", 7) = {1};
