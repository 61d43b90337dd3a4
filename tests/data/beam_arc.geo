// A gmsh curve (a circular arc inside the unit cube) meshed as a polyline: apps/beam_solid
// rejects it with a one-line error (the torsion-free beam needs straight reference fibres).
DefineConstant[ refine = 1 ];
Point(1) = {0, 0.2, 0.3}; Point(2) = {1, 0.2, 0.3}; Point(3) = {0.5, 0.2, -0.225};
Circle(1) = {1, 3, 2};
Transfinite Curve{1} = 10 * refine + 1;
Physical Curve("fibre", 1) = {1};
