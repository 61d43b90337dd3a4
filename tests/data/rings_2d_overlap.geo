// Bad input for the initial-overlap check (tests/CMakeLists.txt): the 3 x 2 rings of
// meshes/rings_2d_small.geo with gap = -1, so neighbouring rings (and plate and walls) overlap
// by 1 mm in the mesh. Written for this project.
nx = 3; ny = 2; gap = -1;
Include "../../meshes/rings_2d.geo";
