// Meshes from gmsh: a .geo source is meshed by the gmsh executable (on rank 0, with
// `-setnumber refine N`), a .msh file is read directly. Physical volumes (2D: surfaces) become
// deal.II material ids, physical surfaces (2D: lines) boundary ids.
#pragma once

#include <deal.II/grid/tria.h>

#include <mpi.h>

#include <string>

namespace physics
{
  /// The .msh file to read for `file`: `file` itself, or for a .geo source the mesh gmsh makes of
  /// it on rank 0 (`-<dimension> -setnumber refine N -format msh22`, kept in `work_directory`).
  /// Throws std::invalid_argument naming the file if it is missing or gmsh fails.
  std::string gmsh_mesh(const std::string& file, int dimension, int refinement, const std::string& work_directory,
                        MPI_Comm comm);

  /// Fills `tria` (empty) from `file`. Throws std::invalid_argument with a one-line message
  /// naming the file for a missing file, a gmsh failure or a mesh deal.II cannot read
  /// (quadrilaterals/hexahedra expected; gmsh log kept in `work_directory`).
  template <int dim>
  void read_mesh(const std::string& file, int refinement, const std::string& work_directory,
                 dealii::Triangulation<dim>& tria, MPI_Comm comm);
} // namespace physics
