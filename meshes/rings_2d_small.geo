// The collapsing rings of meshes/rings_2d.geo, 3 x 2 rings (the rings ctest and quick trials):
// bodies 1..6 rings, 7 plate, 8 container; boundary ids as there.
nx = 3; ny = 2;
Include "rings_2d.geo";
