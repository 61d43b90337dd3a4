// Collapsing rings, 2D plane strain (seed 000, BENCHMARKS.md §1): ny rows of nx hollow rings
// (annuli of outer radius R and wall thickness t) stacked in columns inside a U-shaped container
// (floor and two walls, clamped on its outside) under a pressing plate (loaded on its top face);
// every ring is a body of its own. Neighbours are `gap` apart at the start, the outer rings
// `side` from the walls. stagger = 1 puts the rows on a triangular lattice instead (nx rings in
// the even rows, nx - 1 shifted by half a pitch in the odd ones, each resting in the pocket of
// two below); the defaults (side = gap, stagger = 0) are the square columns of the README's runs.
// Each ring: four transfinite quadrilateral patches, 8*refine elements per quarter circle and
// 2*refine through the wall (after the subdivision of every quadrilateral into four that makes
// the recombined container and plate all-quadrilateral).
// Material ids (bodies): ring k = 1 .. N, row by row from the bottom (N = nx*ny; staggered
// ceil(ny/2) nx + floor(ny/2) (nx - 1)), plate N + 1, container N + 2 (the highest id: with
// automatic pairs it is master only, and each ring is slave toward the plate and toward the
// rings above and right of it).
// Boundary ids: 1 ring outer surfaces (contact), 2 container inner surface and plate bottom
// (contact), 3 container outside (clamped), 4 plate top (loaded), 5 ring inner surfaces (checked
// for self-contact only); the plate's sides are free (as contact faces their top nodes, slave and
// fully prescribed, would be left out of every AMG aggregate).
// Mesh it alone: gmsh -2 -setnumber nx 6 -setnumber ny 4 meshes/rings_2d.geo
Geometry.AutoCoherence = 0;
DefineConstant[ refine = 1, nx = 6, ny = 4, R = 50, t = 10, gap = 2, side = 2, stagger = 0 ];
nq = 4 * refine;   // elements per quarter circle before the subdivision
nt = refine;       // elements through the ring wall before the subdivision
w  = 0.5 * R;      // container wall and plate thickness
hb = 0.5 * R / refine; // element size of container and plate before the subdivision

inner_width = nx * 2 * R + (nx - 1) * gap + 2 * side;
pitch_x     = 2 * R + gap;                                  // centre distance within a row
pitch_y     = stagger ? 0.5 * Sqrt(3) * pitch_x : pitch_x;   // centre distance between rows
pile_top    = 2 * R + (ny - 1) * pitch_y + 2 * gap;
nrings      = 0;

outer[] = {}; inner[] = {};
For j In {0 : ny - 1}
  odd = stagger && j % 2;
  For i In {0 : nx - 1 - odd}
    cx = side + R + i * pitch_x + odd * 0.5 * pitch_x;
    cy = gap + R + j * pitch_y;
    nrings++;
    c  = newp; Point(c) = {cx, cy, 0};
    po = newp;
    Point(po) = {cx + R, cy, 0}; Point(po + 1) = {cx, cy + R, 0};
    Point(po + 2) = {cx - R, cy, 0}; Point(po + 3) = {cx, cy - R, 0};
    pi = newp;
    Point(pi) = {cx + R - t, cy, 0}; Point(pi + 1) = {cx, cy + R - t, 0};
    Point(pi + 2) = {cx - R + t, cy, 0}; Point(pi + 3) = {cx, cy - R + t, 0};
    lo = newl;
    For q In {0 : 3}
      Circle(lo + q) = {po + q, c, po + (q + 1) % 4};
    EndFor
    li = newl;
    For q In {0 : 3}
      Circle(li + q) = {pi + q, c, pi + (q + 1) % 4};
    EndFor
    lr = newl;
    For q In {0 : 3}
      Line(lr + q) = {pi + q, po + q};
    EndFor
    patches[] = {};
    For q In {0 : 3}
      cl = newll; Curve Loop(cl) = {lr + q, lo + q, -(lr + (q + 1) % 4), -(li + q)};
      s = news; Plane Surface(s) = {cl};
      patches[] += s;
    EndFor
    Transfinite Curve{lo : lo + 3, li : li + 3} = nq + 1;
    Transfinite Curve{lr : lr + 3} = nt + 1;
    Transfinite Surface{patches[]};
    Recombine Surface{patches[]};
    Physical Surface(nrings) = {patches[]};
    outer[] += {lo : lo + 3};
    inner[] += {li : li + 3};
  EndFor
EndFor

// Pressing plate, `gap` above the top row, `gap` from each wall.
p = newp;
Point(p) = {gap, pile_top, 0, hb}; Point(p + 1) = {inner_width - gap, pile_top, 0, hb};
Point(p + 2) = {inner_width - gap, pile_top + w, 0, hb}; Point(p + 3) = {gap, pile_top + w, 0, hb};
l = newl;
Line(l) = {p, p + 1}; Line(l + 1) = {p + 1, p + 2}; Line(l + 2) = {p + 2, p + 3}; Line(l + 3) = {p + 3, p};
cl = newll; Curve Loop(cl) = {l : l + 3};
plate = news; Plane Surface(plate) = {cl};
Physical Surface(nrings + 1) = {plate};

// Container: floor and walls as one U-shaped body, walls up to the plate's top plus 2 R.
top = pile_top + w + 2 * R;
k = newp;
Point(k) = {-w, -w, 0, hb}; Point(k + 1) = {inner_width + w, -w, 0, hb};
Point(k + 2) = {inner_width + w, top, 0, hb}; Point(k + 3) = {inner_width, top, 0, hb};
Point(k + 4) = {inner_width, 0, 0, hb}; Point(k + 5) = {0, 0, 0, hb};
Point(k + 6) = {0, top, 0, hb}; Point(k + 7) = {-w, top, 0, hb};
m = newl;
For q In {0 : 7}
  Line(m + q) = {k + q, k + (q + 1) % 8};
EndFor
cl = newll; Curve Loop(cl) = {m : m + 7};
box = news; Plane Surface(box) = {cl};
Recombine Surface{plate, box};
Mesh.SubdivisionAlgorithm = 1;
Physical Surface(nrings + 2) = {box};

Physical Curve("ring_outer", 1) = {outer[]};
Physical Curve("contact_walls", 2) = {l, m + 3, m + 4, m + 5};
Physical Curve("clamped", 3) = {m, m + 1, m + 7};
Physical Curve("plate_top", 4) = {l + 2};
Physical Curve("ring_inner", 5) = {inner[]};
