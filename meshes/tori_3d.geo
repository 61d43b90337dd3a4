// Two tori impact, 3D (seed 000, BENCHMARKS.md §1; apps/contact_tori_3d.prm): two hollow,
// thick-walled tori of major radius R, tube radius r and wall t. Torus 1 lies in the xy-plane
// around the origin; torus 2 is turned 90 degrees (it lies in the xz-plane) and sits above torus
// 1's tube at x = R, `gap` apart, so that the two tubes cross at right angles where they meet.
// Each torus: its annular tube section (four transfinite quadrilateral patches, nq elements per
// quarter of the tube's circumference, nt through the wall) revolved around the torus axis in
// four quarter turns of nl layers each: hexahedra only, nodes matching across the quarters.
// Material ids (bodies): torus 1 = 1, torus 2 = 2 (with automatic pairs torus 1 is the slave).
// Boundary ids: 1 outer surfaces (contact), 5 inner surfaces of the tubes (not contact).
// Mesh it alone: gmsh -3 [-setnumber refine 2] meshes/tori_3d.geo
DefineConstant[ refine = 1, R = 100, r = 25, t = 5, gap = 2 ];
// stacked = 1: torus 2 lies coaxially on top of torus 1 (not turned), so that the tubes meet
// along a whole circle (a line contact with many active nodes instead of the crossing's few).
DefineConstant[ stacked = 0 ];
nq = 5 * refine;  // elements per quarter of the tube's circumference
nt = 2 * refine;  // elements through the wall
nl = 10 * refine; // layers per quarter turn around the torus axis
// refine = 1: 2 x 3200 hexahedra, 4800 nodes; each increment of refine multiplies both by about
// refine^3 (refine = 4: about 300 000 nodes, the seeds' size).

outer_surfaces[] = {};
inner_surfaces[] = {};

// Point `pt` at (R + u) e[] + v a[] from (ox, oy, oz) (a section point of the torus below); pt++.
Macro SectionPoint
  Point(pt) = {ox + (R + u) * e[0] + v * a[0], oy + (R + u) * e[1] + v * a[1], oz + (R + u) * e[2] + v * a[2]};
  pt++;
Return

// One hollow torus around the axis through (ox, oy, oz) along the unit vector a[], its tube
// section drawn in the plane of a[] and the radial unit vector e[] (at distance R from the axis):
// returns its volumes in torus[] and adds its outer and inner faces to the lists. Each torus is
// built where it stays (transforming an extruded mesh's entities afterwards breaks its layers).
Macro HollowTorus
  pt = newp;
  // (One Call per line: gmsh runs a macro called mid-line after the rest of the line.)
  c = pt;
  u = 0; v = 0;
  Call SectionPoint;
  po = pt;
  For q In {0 : 3} // outer circle, then inner circle: at angles q pi / 2 in the (e, a) plane
    u = r * Cos(q * Pi / 2); v = r * Sin(q * Pi / 2);
    Call SectionPoint;
  EndFor
  pn = pt;
  For q In {0 : 3}
    u = (r - t) * Cos(q * Pi / 2); v = (r - t) * Sin(q * Pi / 2);
    Call SectionPoint;
  EndFor
  lo = newl;
  For q In {0 : 3}
    Circle(lo + q) = {po + q, c, po + (q + 1) % 4};
  EndFor
  li = newl;
  For q In {0 : 3}
    Circle(li + q) = {pn + q, c, pn + (q + 1) % 4};
  EndFor
  lr = newl;
  For q In {0 : 3}
    Line(lr + q) = {pn + q, po + q};
  EndFor
  section[] = {};
  For q In {0 : 3}
    cl = newll; Curve Loop(cl) = {lr + q, lo + q, -(lr + (q + 1) % 4), -(li + q)};
    s = news; Plane Surface(s) = {cl};
    section[] += s;
  EndFor
  Transfinite Curve{lo : lo + 3, li : li + 3} = nq + 1;
  Transfinite Curve{lr : lr + 3} = nt + 1;
  Transfinite Surface{section[]};
  Recombine Surface{section[]};
  // Four quarter turns (a revolution must stay below pn per extrusion). Extrude returns, per
  // surface, [top, volume, side faces in the order of the curve loop: radial, outer, radial,
  // inner].
  torus[] = {};
  current[] = section[];
  For turn In {0 : 3}
    next[] = {};
    For q In {0 : 3}
      ex[] = Extrude { {a[0], a[1], a[2]}, {ox, oy, oz}, Pi / 2 } { Surface{current[q]}; Layers{nl}; Recombine; };
      next[] += ex[0];
      torus[] += ex[1];
      outer_surfaces[] += ex[3];
      inner_surfaces[] += ex[5];
    EndFor
    current[] = next[];
  EndFor
Return

// Torus 1: axis z through the origin.
ox = 0; oy = 0; oz = 0; a[] = {0, 0, 1}; e[] = {1, 0, 0};
Call HollowTorus;
torus1[] = torus[];
// Torus 2: axis y through (R, 0, R + 2 r + gap), so that its lowest point (x = R, z = r + gap)
// lies `gap` above torus 1's top (x = R, z = r).
ox = R; oy = 0; oz = R + 2 * r + gap; a[] = {0, 1, 0}; e[] = {0, 0, 1};
If (stacked)
  // Axis z through (0, 0, 2 r + gap): its bottom circle lies `gap` above torus 1's top circle.
  ox = 0; oy = 0; oz = 2 * r + gap; a[] = {0, 0, 1}; e[] = {1, 0, 0};
EndIf
Call HollowTorus;
torus2[] = torus[];
// The last quarter's top faces coincide with the first quarter's section: merge them (and every
// other duplicate point, curve and face) so that each torus is one conforming mesh.
Coherence;

Physical Volume(1) = {torus1[]};
Physical Volume(2) = {torus2[]};
Physical Surface("outer", 1) = {outer_surfaces[]};
Physical Surface("inner", 5) = {inner_surfaces[]};
