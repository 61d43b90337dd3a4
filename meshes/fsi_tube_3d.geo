// Pressure-wave tube (BENCHMARKS.md section 3, Gerbeau-Vidrascu) in CGS units: a straight tube
// along x of length 5 cm, fluid radius R = 0.5 cm, wall 0.1 cm (outer radius 0.6 cm).
// The fluid cylinder is an O-grid (a square core and four blocks out to the circle r = R), the
// wall four blocks of the annulus R < r < R + h; both volumes share the interface surface, so
// fluid and structure nodes match there. All hexahedra (transfinite + recombined, extruded).
//   gmsh -3 -setnumber refine N -format msh22 fsi_tube_3d.geo
//   refine 1: 8 cells around, 20 along; refine 2: 16 around, 40 along; ...
// Physical ids: volumes 1 fluid, 2 structure; surfaces 1 the inlet plane x = 0 (fluid inlet and
// the structure's clamped end), 2 the outlet plane x = L, 5 the outer wall r = R + h. The
// interface r = R is interior to this mesh: the fsi app finds it where the two volumes meet.
DefineConstant[ refine = 1 ];
L = 5; R = 0.5; h = 0.1;
s = 0.35 * R;          // half side of the core square
nq = 2 * refine;       // cells per quarter of the circumference (and per side of the core)
nr = refine;           // cells from the core to the interface
nw = refine;           // cells through the wall
nx = 20 * refine;      // cells along the tube

c = 1 / Sqrt(2);
Point(1) = {0, 0, 0};
// core square, interface circle and outer circle: one point each at 45, 135, 225, 315 degrees
For k In {0 : 3}
  a = Pi / 4 + k * Pi / 2;
  Point(10 + k) = {0, s * Sqrt(2) * Cos(a), s * Sqrt(2) * Sin(a)};
  Point(20 + k) = {0, R * Cos(a), R * Sin(a)};
  Point(30 + k) = {0, (R + h) * Cos(a), (R + h) * Sin(a)};
EndFor
For k In {0 : 3}
  k1 = (k + 1) % 4;
  Line(10 + k) = {10 + k, 10 + k1};        // core sides
  Circle(20 + k) = {20 + k, 1, 20 + k1};   // interface arcs
  Circle(30 + k) = {30 + k, 1, 30 + k1};   // outer arcs
  Line(40 + k) = {10 + k, 20 + k};         // core -> interface
  Line(50 + k) = {20 + k, 30 + k};         // interface -> outer
EndFor
Transfinite Curve{10 : 13, 20 : 23, 30 : 33} = nq + 1;
Transfinite Curve{40 : 43} = nr + 1;
Transfinite Curve{50 : 53} = nw + 1;

Curve Loop(1) = {10, 11, 12, 13};
Plane Surface(1) = {1};
For k In {0 : 3}
  k1 = (k + 1) % 4;
  Curve Loop(10 + k) = {10 + k, 40 + k1, -(20 + k), -(40 + k)};
  Plane Surface(10 + k) = {10 + k};
  Curve Loop(20 + k) = {20 + k, 50 + k1, -(30 + k), -(50 + k)};
  Plane Surface(20 + k) = {20 + k};
EndFor
Transfinite Surface{1, 10 : 13, 20 : 23};
Recombine Surface{1, 10 : 13, 20 : 23};

// Extrude the cross-section along x; out[0] is the far face, out[1] the volume, out[2..] the sides.
fluid[] = {};
wall[] = {};
outlet[] = {};
outer[] = {};
core[] = Extrude {L, 0, 0} { Surface{1}; Layers{nx}; Recombine; };
fluid += core[1];
outlet += core[0];
For k In {0 : 3}
  ring[] = Extrude {L, 0, 0} { Surface{10 + k}; Layers{nx}; Recombine; };
  fluid += ring[1];
  outlet += ring[0];
  shell[] = Extrude {L, 0, 0} { Surface{20 + k}; Layers{nx}; Recombine; };
  wall += shell[1];
  outlet += shell[0];
  outer += shell[4]; // the side extruded from the outer arc 30 + k (third curve of the loop)
EndFor

Physical Volume("fluid", 1) = {fluid[]};
Physical Volume("structure", 2) = {wall[]};
Physical Surface("inlet", 1) = {1, 10 : 13, 20 : 23};
Physical Surface("outlet", 2) = {outlet[]};
Physical Surface("outer", 5) = {outer[]};
