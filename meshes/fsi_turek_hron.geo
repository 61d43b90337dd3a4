// The Turek-Hron FSI benchmark channel (Turek & Hron 2006, "Proposal for numerical benchmarking
// of fluid-structure interaction between an elastic object and laminar incompressible flow";
// BENCHMARKS.md section 3), SI units: the channel [0, 2.5] x [0, 0.41] m, a rigid cylinder of
// radius 0.05 centred at (0.2, 0.2), and an elastic flag 0.35 x 0.02 attached to its downstream
// side, from the cylinder to x = 0.6, y in [0.19, 0.21]. Point A = (0.6, 0.2), the middle of the
// flag's free end, is a mesh node (its displacement is the benchmark's monitored value).
//   gmsh -2 -setnumber refine N -format msh22 fsi_turek_hron.geo
// Quadrilaterals only. Around cylinder and flag, in the box [0.1, 1] x [0.1, 0.3], structured
// blocks (transfinite), graded toward the bodies, the same above and below the flag: the flag's
// deflection comes from the small pressure difference between its two sides, and unstructured
// cells there (different above and below) changed it by +-10 % from mesh to mesh. The flag
// itself transfinite. The rest of the channel unstructured (Frontal-Delaunay, recombined), and
// every cell subdivided into four at the end. Cells after the subdivision, refine = 1: the flag
// 8 x 70 (bending of Q1 cells stiffens it by ~3.5 % at this size, ~1 % at refine 2), 28 around
// the front of the cylinder, the first fluid cell 0.003 thick at the bodies; all counts times
// refine.
// Physical ids: surfaces 1 fluid, 2 structure (the flag); lines 1 inlet x = 0, 2 outlet
// x = 2.5, 4 the channel walls y = 0 and y = 0.41, 6 the cylinder (the fluid's arc and the flag's
// clamped end). The flag's other sides are the fluid/structure interface, interior to this mesh:
// the fsi app finds it where the two parts meet.
DefineConstant[ refine = 1 ];
L = 2.5; H = 0.41;               // channel
xc = 0.2; yc = 0.2; r = 0.05;    // cylinder
xf = 0.6; hf = 0.01;             // flag end, half thickness
xb = xc + Sqrt(r * r - hf * hf); // where the flag's sides meet the cylinder
x0 = 0.1; x1 = 1.0; y0 = 0.1; y1 = 0.3; // the structured box
s = r / Sqrt(2);
// The lines from the flag's corners out to the box halve the angle between the flag's side and
// the cylinder there (101.5 degrees), so that no block has a sharp corner.
xq = xb + (y1 - yc - hf) / Tan(0.5 * (Pi / 2 + Asin(hf / r)));

// Cells before the subdivision (each becomes 2 x 2).
n_h = 2 * refine;                // half the flag's thickness
n_f = 35 * refine;               // along the flag
n_r = 8 * refine;                // from the bodies to the box, growing by p_r per cell
p_r = 1.15 ^ (1 / refine);
n_1 = 10 * refine;               // the cylinder's front quarter (135 to 225 degrees)
n_2 = 12 * refine;               // from the flag to 135 degrees (and mirrored)
n_w = 20 * refine;               // the wake from x = 0.6 to x1, growing by p_w per cell
p_w = 1.05 ^ (1 / refine);
far = 0.06 / refine;             // the unstructured cells away from the box

Point(1) = {0, 0, 0};
Point(2) = {L, 0, 0};
Point(3) = {L, H, 0};
Point(4) = {0, H, 0};
Point(10) = {xc, yc, 0};
Point(11) = {xb, yc - hf, 0};     // flag corners on the cylinder
Point(12) = {xb, yc + hf, 0};
Point(13) = {xc - s, yc + s, 0};  // the cylinder at 135 and 225 degrees
Point(14) = {xc - s, yc - s, 0};
Point(21) = {xf, yc - hf, 0};     // flag end
Point(22) = {xf, yc, 0};          // point A
Point(23) = {xf, yc + hf, 0};
Point(31) = {x0, y0, 0};          // the box
Point(32) = {x0, y1, 0};
Point(33) = {xq, y1, 0};
Point(34) = {xf, y1, 0};
Point(35) = {x1, y1, 0};
Point(36) = {x1, yc + hf, 0};
Point(37) = {x1, yc - hf, 0};
Point(38) = {x1, y0, 0};
Point(39) = {xf, y0, 0};
Point(40) = {xq, y0, 0};

Line(1) = {1, 2};   // bottom wall
Line(2) = {2, 3};   // outlet
Line(3) = {3, 4};   // top wall
Line(4) = {4, 1};   // inlet
Circle(11) = {12, 10, 13}; // the fluid's arc: flag (top) to 135 degrees,
Circle(12) = {13, 10, 14}; // the front quarter,
Circle(13) = {14, 10, 11}; // 225 degrees to the flag (bottom)
Circle(15) = {11, 10, 12}; // the flag's clamped end
Line(21) = {11, 21}; // flag bottom
Line(22) = {21, 22}; // flag end, lower half
Line(23) = {22, 23}; // flag end, upper half
Line(24) = {23, 12}; // flag top
Line(31) = {13, 32}; // from the bodies out to the box
Line(32) = {14, 31};
Line(33) = {12, 33};
Line(34) = {11, 40};
Line(35) = {23, 34};
Line(36) = {21, 39};
Line(41) = {23, 36}; // the wake
Line(42) = {21, 37};
Line(43) = {34, 35};
Line(44) = {39, 38};
Line(45) = {36, 35}; // the box's right side
Line(46) = {37, 38};
Line(47) = {37, 36};
Line(51) = {31, 32}; // the box's left, top and bottom sides
Line(52) = {32, 33};
Line(53) = {33, 34};
Line(54) = {31, 40};
Line(55) = {40, 39};

Transfinite Curve{22, 23} = n_h + 1;
Transfinite Curve{15, 47} = 2 * n_h + 1;
Transfinite Curve{21, 24, 53, 55} = n_f + 1;
Transfinite Curve{31, 32, 33, 34, 35, 36, 45, 46} = n_r + 1 Using Progression p_r;
Transfinite Curve{12, 51} = n_1 + 1;
Transfinite Curve{11, 13, 52, 54} = n_2 + 1;
Transfinite Curve{41, 42, 43, 44} = n_w + 1 Using Progression p_w;

Curve Loop(2) = {21, 22, 23, 24, -15};   // the flag
Plane Surface(2) = {2};
Transfinite Surface{2} = {11, 21, 23, 12};
Curve Loop(11) = {12, 32, 51, -31};      // in front of the cylinder
Plane Surface(11) = {11};
Transfinite Surface{11} = {13, 14, 31, 32};
Curve Loop(12) = {11, 31, 52, -33};      // above the cylinder
Plane Surface(12) = {12};
Transfinite Surface{12} = {12, 13, 32, 33};
Curve Loop(13) = {13, 34, -54, -32};     // below the cylinder
Plane Surface(13) = {13};
Transfinite Surface{13} = {14, 11, 40, 31};
Curve Loop(14) = {33, 53, -35, 24};      // above the flag
Plane Surface(14) = {14};
Transfinite Surface{14} = {12, 33, 34, 23};
Curve Loop(15) = {21, 36, -55, -34};     // below the flag
Plane Surface(15) = {15};
Transfinite Surface{15} = {11, 21, 39, 40};
Curve Loop(16) = {41, 45, -43, -35};     // the wake: above,
Plane Surface(16) = {16};
Transfinite Surface{16} = {23, 36, 35, 34};
Curve Loop(17) = {42, 47, -41, -23, -22}; // behind the flag's end,
Plane Surface(17) = {17};
Transfinite Surface{17} = {21, 37, 36, 23};
Curve Loop(18) = {36, 44, -46, -42};     // below
Plane Surface(18) = {18};
Transfinite Surface{18} = {21, 39, 38, 37};

Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(3) = {51, 52, 53, 43, -45, -47, 46, -44, -55, -54};
Plane Surface(1) = {1, 3};               // the rest of the channel
Field[1] = Distance;
Field[1].CurvesList = {51, 52, 53, 43, 45, 47, 46, 44, 55, 54};
Field[1].NumPointsPerCurve = 100;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = 0.015 / refine;
Field[2].SizeMax = far;
Field[2].DistMin = 0;
Field[2].DistMax = 0.5;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 1; // the box sides' spacing near them
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

Mesh.Algorithm = 6;              // Frontal-Delaunay (8, its variant for quads, crashes here in gmsh 4.8)
Recombine Surface{1, 2, 11 : 18};
Mesh.RecombinationAlgorithm = 1; // Blossom
Mesh.SubdivisionAlgorithm = 1;   // all quadrilaterals
Mesh.Smoothing = 5;

Physical Surface("fluid", 1) = {1, 11 : 18};
Physical Surface("structure", 2) = {2};
Physical Curve("inlet", 1) = {4};
Physical Curve("outlet", 2) = {2};
Physical Curve("walls", 4) = {1, 3};
Physical Curve("cylinder", 6) = {11, 12, 13, 15};
