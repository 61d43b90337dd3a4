// The fluid and structure meshes of the condensed FSI app, both fully distributed
// (common/distributed_mesh.h), with the interface nodes of the two meshes at the same places:
//  - the 2D channel between two elastic walls, generated (apps/fsi_channel_2d.prm);
//  - any gmsh mesh with the fluid as physical volume (2D: surface) 1 and the structure as 2 in one
//    conforming mesh (meshes/fsi_tube_3d.geo, meshes/fsi_turek_hron.geo). The two parts are cut
//    apart on the group roots; the faces where they met become the interface of both, so their
//    nodes match by construction.
// Boundary ids of both meshes (the gmsh physical surfaces/lines keep their numbers):
//   1 inlet plane (fluid: the pressure pulse; structure: clamped; ALE: fixed),
//   2 outlet plane (fluid: traction-free; structure: clamped; ALE: fixed),
//   3 fluid/structure interface, 5 the structure's outer surface (traction-free),
//   4 a rigid wall (fluid: no-slip; structure: clamped; ALE: fixed),
//   6 a rigid obstacle (as 4; the fluid's force on obstacle and interface is logged: the
//     Turek-Hron cylinder, meshes/fsi_turek_hron.geo).
// Id 0 is left unused: a fully distributed mesh gives it to the outer faces of its ghost layer.
#pragma once

#include "common/mesh_input.h"

#include <deal.II/distributed/fully_distributed_tria.h>

#include <string>
#include <vector>

namespace physics::fsi::boundary
{
  constexpr unsigned int inlet = 1, outlet = 2, interface = 3, wall = 4, outer = 5, obstacle = 6;
} // namespace physics::fsi::boundary

namespace physics::fsi
{
  /// The generated 2D channel: fluid [0, L] x [0, H] (nx x nf cells), walls [0, L] x [-t, 0] and
  /// [0, L] x [H, H + t] (nxw x nw cells each; nxw = 0: nx, matching interface nodes).
  struct ChannelGeometry
  {
    double       length = 6, height = 1, wall_thickness = 0.1;
    unsigned int cells_x = 30, cells_fluid = 6, cells_wall = 1, cells_wall_x = 0;
  };

  void make_channel_meshes(const ChannelGeometry&                                g,
                           dealii::parallel::fullydistributed::Triangulation<2>& fluid,
                           dealii::parallel::fullydistributed::Triangulation<2>& structure);

  /// Reads the gmsh `file` (.geo meshed with `gmsh`'s refinement and variables, or .msh) and
  /// fills `fluid` with its cells of material id 1 and `structure` with those of material id 2
  /// (material id 0 afterwards), after `global_refinements` uniform refinements of the whole, the faces
  /// between the two marked boundary::interface. Throws std::invalid_argument naming the file when a part is
  /// empty, a material id other than 1 or 2 occurs, the parts do not touch, or the fluid has no inlet face.
  template <int dim>
  void read_fsi_meshes(const std::string& file, const GmshSource& gmsh, int global_refinements,
                       const std::string&                                      work_directory,
                       dealii::parallel::fullydistributed::Triangulation<dim>& fluid,
                       dealii::parallel::fullydistributed::Triangulation<dim>& structure);

  /// Both functions above partition the two meshes with METIS each on its own, then number the
  /// structure's parts after the fluid's with this renumbering: `overlap[s][f]` counts the
  /// interface faces of the structure's part s whose fluid side lies in the fluid's part f; the
  /// result is the new number of each part s, a permutation of 0 ... n-1 that keeps the most
  /// interface faces on one rank (greedy, largest counts first: exact for 2 parts, and for any
  /// number where every structure part meets mainly one fluid part). Parts left without a
  /// partner take the numbers left over, in order.
  std::vector<unsigned int> renumbering_by_overlap(const std::vector<std::vector<unsigned int>>& overlap);
} // namespace physics::fsi
