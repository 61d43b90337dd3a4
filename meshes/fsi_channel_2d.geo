// The 2D counterpart of the pressure-wave tube (BENCHMARKS.md section 3, CGS units): a channel
// of length L = 6 cm and height H = 1 cm between two elastic walls h = 0.1 cm thick, the same
// mesh as the fsi app's built-in channel (apps/fsi_channel_2d.prm: 30 x 6 fluid cells, 1 per
// wall) at refine 1, every cell count times refine. Quadrilaterals only (transfinite, recombined).
//   gmsh -2 -setnumber refine N -format msh22 fsi_channel_2d.geo
// Physical ids: surfaces 1 fluid, 2 structure (both walls); lines 1 the inlet plane x = 0 (fluid
// inlet and the walls' clamped ends), 2 the outlet plane x = L, 5 the walls' outer sides. The
// interfaces y = 0 and y = H are interior to this mesh: the fsi app finds them where the two
// parts meet.
DefineConstant[ refine = 1 ];
L = 6; H = 1; h = 0.1;
nx = 30 * refine; // cells along the channel
ny = 6 * refine;  // fluid cells across
nw = refine;      // cells across each wall

// Points at x = 0 and x = L on the lines y = -h, 0, H, H + h.
ys[] = {-h, 0, H, H + h};
For k In {0 : 3}
  Point(1 + k) = {0, ys[k], 0};
  Point(11 + k) = {L, ys[k], 0};
EndFor
For k In {0 : 3}
  Line(1 + k) = {1 + k, 11 + k}; // along x
EndFor
For k In {0 : 2}
  Line(11 + k) = {1 + k, 2 + k};  // inlet side, layer k
  Line(21 + k) = {11 + k, 12 + k}; // outlet side, layer k
EndFor
Transfinite Curve{1 : 4} = nx + 1;
Transfinite Curve{11, 13, 21, 23} = nw + 1;
Transfinite Curve{12, 22} = ny + 1;
For k In {0 : 2}
  Curve Loop(1 + k) = {1 + k, 21 + k, -(2 + k), -(11 + k)};
  Plane Surface(1 + k) = {1 + k};
EndFor
Transfinite Surface{1 : 3};
Recombine Surface{1 : 3};

Physical Surface("fluid", 1) = {2};
Physical Surface("structure", 2) = {1, 3};
Physical Curve("inlet", 1) = {11 : 13};
Physical Curve("outlet", 2) = {21 : 23};
Physical Curve("outer", 5) = {1, 4};
