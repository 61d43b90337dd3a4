// Pressure-wave tube (BENCHMARKS.md section 3, Gerbeau-Vidrascu) in CGS units: a straight tube
// along x of length 5 cm, fluid radius R = 0.5 cm, wall 0.1 cm (outer radius 0.6 cm).
// The fluid cylinder is an O-grid (a square core, four blocks out to r = R - layer and a thin ring
// of cells R - layer < r < R at the wall), the wall four blocks of the annulus R < r < R + h; both
// volumes share the interface surface, so fluid and structure nodes match there. All hexahedra
// (transfinite + recombined, extruded).
// Why the thin ring: the fluid sticks to the wall (no slip), so the axial velocity of equal-order
// Q1 falls to zero across the whole first cell. Without the ring that cell reached from the core
// to the wall (0.25-0.33 cm of R = 0.5 at refine 1): for a linear profile across it the flow's
// effective cross-section is about 0.6 A, and the pulse (c ~ sqrt(A_eff / (rho_F A D))) ran 17 %
// below Moens-Korteweg (12 % with the ring at refine 1, see README). The
// physical Stokes layer of the pulse is sqrt(nu / omega) ~ 0.005 cm thin; a ring 0.02 / refine cm
// thick leaves about 1 - layer / R of the cross-section to the flow.
//   gmsh -3 -setnumber refine N -format msh22 fsi_tube_3d.geo
//   refine 1: 8 cells around, 20 along; refine 2: 16 around, 40 along; ...
// Physical ids: volumes 1 fluid, 2 structure; surfaces 1 the inlet plane x = 0 (fluid inlet and
// the structure's clamped end), 2 the outlet plane x = L, 5 the outer wall r = R + h. The
// interface r = R is interior to this mesh: the fsi app finds it where the two volumes meet.
// Non-matching along x: -setnumber wall_cells M (M != 20 refine) gives the wall M cells along
// the tube on an interface surface of its own (the same arcs around, other nodes along x); both
// interface surfaces are then physical surface 3 (the fsi app needs Coupling/Interface = dual
// mortar). wall_cells = 0 (default): the matching mesh above.
// Wall thickness: -setnumber wall H (default 0.1 cm, the benchmark's). A thinner wall with E h
// kept (E = 3e6 x 0.1 / H) has the same Moens-Korteweg speed and a smaller thick-wall correction:
// the check that the measured speed tends to the thin-wall formula as h / R -> 0 (README).
// Length: -setnumber length L (default 5 cm) with 4 refine cells per cm along the tube (the
// cross-section unchanged): the DOFs grow in proportion to L (weak-scaling studies, a longer
// record of the pulse).
DefineConstant[ refine = 1, wall_cells = 0, wall = 0.1, length = 5 ];
L = length; R = 0.5; h = wall;
layer = 0.02 / refine; // thickness of the fluid cells at the wall (halves with the rest)
s = 0.35 * R;          // half side of the core square
nq = 2 * refine;       // cells per quarter of the circumference (and per side of the core)
nr = refine;           // cells from the core to the wall layer
nw = refine;           // cells through the wall
nx = Floor(4 * refine * L + 0.5); // cells along the tube (20 refine for L = 5)

nxw = wall_cells > 0 ? wall_cells : nx; // cells along the wall
apart = wall_cells > 0;                  // the wall on an interface surface of its own
If (apart)
  Geometry.AutoCoherence = 0; // keep the wall's interface points apart from the fluid's
EndIf

c = 1 / Sqrt(2);
Point(1) = {0, 0, 0};
// core square, interface circle and outer circle: one point each at 45, 135, 225, 315 degrees
For k In {0 : 3}
  a = Pi / 4 + k * Pi / 2;
  Point(10 + k) = {0, s * Sqrt(2) * Cos(a), s * Sqrt(2) * Sin(a)};
  Point(20 + k) = {0, R * Cos(a), R * Sin(a)};
  Point(30 + k) = {0, (R + h) * Cos(a), (R + h) * Sin(a)};
  Point(60 + k) = {0, (R - layer) * Cos(a), (R - layer) * Sin(a)};
  If (apart)
    Point(80 + k) = {0, R * Cos(a), R * Sin(a)}; // the wall's own interface points
  EndIf
EndFor
wi = apart ? 80 : 20; // the wall's interface points and arcs
For k In {0 : 3}
  k1 = (k + 1) % 4;
  Line(10 + k) = {10 + k, 10 + k1};        // core sides
  Circle(20 + k) = {20 + k, 1, 20 + k1};   // interface arcs
  Circle(30 + k) = {30 + k, 1, 30 + k1};   // outer arcs
  Circle(60 + k) = {60 + k, 1, 60 + k1};   // inner circle of the wall layer
  Line(40 + k) = {10 + k, 60 + k};         // core -> wall layer
  Line(70 + k) = {60 + k, 20 + k};         // wall layer -> interface
  Line(50 + k) = {wi + k, 30 + k};         // interface -> outer
  If (apart)
    Circle(80 + k) = {80 + k, 1, 80 + k1}; // the wall's interface arcs
  EndIf
EndFor
Transfinite Curve{10 : 13, 20 : 23, 30 : 33, 60 : 63} = nq + 1;
If (apart)
  Transfinite Curve{80 : 83} = nq + 1;
EndIf
Transfinite Curve{70 : 73} = 2;
Transfinite Curve{40 : 43} = nr + 1;
Transfinite Curve{50 : 53} = nw + 1;

Curve Loop(1) = {10, 11, 12, 13};
Plane Surface(1) = {1};
For k In {0 : 3}
  k1 = (k + 1) % 4;
  Curve Loop(10 + k) = {10 + k, 40 + k1, -(60 + k), -(40 + k)};
  Plane Surface(10 + k) = {10 + k};
  Curve Loop(30 + k) = {60 + k, 70 + k1, -(20 + k), -(70 + k)};
  Plane Surface(30 + k) = {30 + k};
  Curve Loop(20 + k) = {wi + k, 50 + k1, -(30 + k), -(50 + k)};
  Plane Surface(20 + k) = {20 + k};
EndFor
Transfinite Surface{1, 10 : 13, 20 : 23, 30 : 33};
Recombine Surface{1, 10 : 13, 20 : 23, 30 : 33};

// Extrude the cross-section along x; out[0] is the far face, out[1] the volume, out[2..] the sides.
fluid[] = {};
wall[] = {};
outlet[] = {};
outer[] = {};
interface[] = {};
core[] = Extrude {L, 0, 0} { Surface{1}; Layers{nx}; Recombine; };
fluid += core[1];
outlet += core[0];
For k In {0 : 3}
  ring[] = Extrude {L, 0, 0} { Surface{10 + k}; Layers{nx}; Recombine; };
  fluid += ring[1];
  outlet += ring[0];
  film[] = Extrude {L, 0, 0} { Surface{30 + k}; Layers{nx}; Recombine; };
  fluid += film[1];
  outlet += film[0];
  shell[] = Extrude {L, 0, 0} { Surface{20 + k}; Layers{nxw}; Recombine; };
  wall += shell[1];
  outlet += shell[0];
  outer += shell[4]; // the side extruded from the outer arc 30 + k (third curve of the loop)
  interface += {film[4], shell[2]}; // the two sides at r = R (one surface when matching)
EndFor

Physical Volume("fluid", 1) = {fluid[]};
Physical Volume("structure", 2) = {wall[]};
Physical Surface("inlet", 1) = {1, 10 : 13, 20 : 23, 30 : 33};
Physical Surface("outlet", 2) = {outlet[]};
Physical Surface("outer", 5) = {outer[]};
If (apart)
  Physical Surface("interface", 3) = {interface[]};
EndIf
