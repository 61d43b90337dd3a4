// Two-block contact benchmark, 2D (plane strain) counterpart of BENCHMARKS.md section 1:
// lower block 1.0 x 0.5 m (master body), upper block 0.8 x 0.4 m centred on it (slave body),
// touching at y = 0.5 with non-matching meshes (10 vs 7 elements per metre times `refine`).
//   gmsh -2 -setnumber refine N -format msh22 two_blocks_2d.geo
// Physical ids: bodies 1 (lower/master), 2 (upper/slave); boundaries 1 slave face (upper
// bottom), 2 master face (lower top), 3 clamped (lower bottom), 4 loaded (upper top).
Geometry.AutoCoherence = 0; // keep coincident points of the two bodies apart
DefineConstant[ refine = 1 ];
DefineConstant[ prescribed_sides = 0 ]; // 1: the upper block's sides move with its top face
nl = 10 * refine; hl = 5 * refine;   // lower block elements (x, y)
nu = 7 * refine;  hu = 4 * refine;   // upper block elements (x, y)

Point(1) = {0, 0, 0};     Point(2) = {1, 0, 0};     Point(3) = {1, 0.5, 0};   Point(4) = {0, 0.5, 0};
Point(5) = {0.1, 0.5, 0}; Point(6) = {0.9, 0.5, 0}; Point(7) = {0.9, 0.9, 0}; Point(8) = {0.1, 0.9, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Transfinite Curve{1, 3} = nl + 1; Transfinite Curve{2, 4} = hl + 1;
Transfinite Curve{5, 7} = nu + 1; Transfinite Curve{6, 8} = hu + 1;
Transfinite Surface{1, 2};
Recombine Surface{1, 2};

Physical Surface("master_body", 1) = {1};
Physical Surface("slave_body", 2) = {2};
Physical Curve("slave", 1) = {5};
Physical Curve("master", 2) = {3};
Physical Curve("clamped", 3) = {1};
If (prescribed_sides)
  // The slave surface's end nodes then have every component prescribed (tests of that case).
  Physical Curve("loaded", 4) = {6, 7, 8};
Else
  Physical Curve("loaded", 4) = {7};
EndIf
