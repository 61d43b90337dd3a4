// The 3D two-block contact benchmark (two_blocks_3d.geo) with a finer choice of sizes, for
// weak-scaling studies (postprocess/weak_scaling.py): `refine` is the number of elements per
// metre of the lower block (two_blocks_3d.geo's refine N is refine = 10 N here), so that the
// DOFs can follow a doubling of the ranks (about 2.1 refine^3 DOFs).
//   gmsh -3 -setnumber refine 25 -format msh22 two_blocks_3d_weak.geo
// Element counts (rounded to the nearest integer, at least 1): lower block refine x refine x
// refine/2, upper block 0.7 refine x 0.7 refine x 0.4 refine. Physical ids as in two_blocks_3d.geo.
Geometry.AutoCoherence = 0; // keep coincident points of the two bodies apart
DefineConstant[ refine = 10 ];
nl = Max(1, Floor(refine + 0.5));       hl = Max(1, Floor(0.5 * refine + 0.5));
nu = Max(1, Floor(0.7 * refine + 0.5)); hu = Max(1, Floor(0.4 * refine + 0.5));

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
Physical Surface("loaded", 4) = {upper[0]};
