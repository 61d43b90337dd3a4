// Three straight fibres inside the unit cube (a beam mesh for apps/beam_solid: set
// "Fibres/Beam file = meshes/fibre_bundle.geo"); gmsh -1 splits each line into 8 elements.
DefineConstant[ refine = 1 ];
n = 8 * refine;
Point(1) = {0.0, 0.31, 0.27}; Point(2) = {1.0, 0.31, 0.47};
Point(3) = {0.0, 0.52, 0.55}; Point(4) = {1.0, 0.62, 0.55};
Point(5) = {0.05, 0.8, 0.2};  Point(6) = {0.95, 0.7, 0.8};
Line(1) = {1, 2}; Line(2) = {3, 4}; Line(3) = {5, 6};
Transfinite Curve{1, 2, 3} = n + 1;
Physical Curve("fibres", 1) = {1, 2, 3};
