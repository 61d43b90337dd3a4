// Two-block contact benchmark (seed 001, BENCHMARKS.md section 1): a 0.8 x 0.8 x 0.4 m block
// (slave body) centred on a 1.0 x 1.0 x 0.5 m block (master body), touching at z = 0.5 with
// non-matching hexahedral meshes (10 vs 7 elements per metre times `refine`).
//   gmsh -3 -setnumber refine N -format msh22 two_blocks_3d.geo
//   refine 1, 2, 3: about 3.1k, 21k, 65k displacement DOFs.
// Physical ids: bodies 1 (lower/master), 2 (upper/slave); boundaries 1 slave face (upper
// bottom), 2 master face (lower top), 3 clamped (lower bottom), 4 loaded (upper top).
Geometry.AutoCoherence = 0; // keep coincident points of the two bodies apart
DefineConstant[ refine = 1 ];
DefineConstant[ prescribed_sides = 0 ]; // 1: the upper block's sides move with its top face
nl = 10 * refine; hl = 5 * refine;
nu = 7 * refine;  hu = 4 * refine;

Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 1, 0}; Point(4) = {0, 1, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = nl + 1; Transfinite Surface{1}; Recombine Surface{1};
lower[] = Extrude {0, 0, 0.5} { Surface{1}; Layers{hl}; Recombine; };

Point(101) = {0.1, 0.1, 0.5}; Point(102) = {0.9, 0.1, 0.5}; Point(103) = {0.9, 0.9, 0.5}; Point(104) = {0.1, 0.9, 0.5};
Line(101) = {101, 102}; Line(102) = {102, 103}; Line(103) = {103, 104}; Line(104) = {104, 101};
Curve Loop(101) = {101, 102, 103, 104}; Plane Surface(101) = {101};
Transfinite Curve{101, 102, 103, 104} = nu + 1; Transfinite Surface{101}; Recombine Surface{101};
upper[] = Extrude {0, 0, 0.4} { Surface{101}; Layers{hu}; Recombine; };

Physical Volume("master_body", 1) = {lower[1]};
Physical Volume("slave_body", 2) = {upper[1]};
Physical Surface("slave", 1) = {101};
Physical Surface("master", 2) = {lower[0]};
Physical Surface("clamped", 3) = {1};
If (prescribed_sides)
  // The slave face's edge nodes then have every component prescribed (tests of that case).
  Physical Surface("loaded", 4) = {upper[0], upper[2], upper[3], upper[4], upper[5]};
Else
  Physical Surface("loaded", 4) = {upper[0]};
EndIf
