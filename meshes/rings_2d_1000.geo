// The seeds' full size of the collapsing rings (seed 000: 1000 rings, about 110 000 nodes): the
// rings of meshes/rings_2d.geo, 40 x 25 of them; at refine 1 the mesh has 100 628 nodes
// (201 256 displacement DOFs). Bodies 1..1000 rings, 1001 plate, 1002 container; boundary ids as
// in rings_2d.geo. Mesh it alone: gmsh -2 meshes/rings_2d_1000.geo (about 10 s).
nx = 40; ny = 25;
Include "rings_2d.geo";
