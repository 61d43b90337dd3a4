// A .geo that gmsh refuses (a syntax error): the app must stop with one line naming gmsh's log.
Point(1) = {0, 0, 0};
this is not gmsh syntax;
