// Fully distributed meshes (parallel::fullydistributed::Triangulation): every rank stores only
// its own cells and one layer of ghost cells, so memory per rank follows the DOFs per rank, not
// the size of the whole problem.
//
// The mesh is built "in groups" (deal.II's TriangulationDescription, the approach of the
// fullydistributed tutorials): the ranks are split into groups of consecutive ranks, one group
// per compute node (the ranks that share memory); only the first rank of each group builds the
// serial mesh (reads or generates it, refines it), partitions it with METIS into one part per
// rank and sends every rank of its group the description of its part. The serial mesh is
// released before any DOF exists, so the largest memory of a run is reached later, by the
// matrices and hierarchies, which are distributed.
#pragma once

#include "common/mesh_input.h"

#include <deal.II/base/function.h>
#include <deal.II/distributed/fully_distributed_tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/component_mask.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>

#include <mpi.h>

#include <functional>
#include <string>
#include <vector>

namespace physics
{
  /// Marks the cells of a serial mesh whose work does not follow their number: the cells at a
  /// contact surface, whose owners evaluate the mortar integrals of their faces, or the cells
  /// beams cross (beam/solid coupling). Empty: none.
  template <int dim>
  using CellMarker = std::function<bool(const typename dealii::Triangulation<dim>::active_cell_iterator&)>;

  /// Called on each group root with the serial mesh once METIS has set its subdomain ids (one part
  /// per rank); it may renumber the parts (a permutation of the ids keeps every part's size), e.g.
  /// so that the parts of a second mesh lie where the same-numbered parts of a first one do.
  template <int dim>
  using PartitionHook = std::function<void(dealii::Triangulation<dim>&)>;

  /// Fills `tria` (empty) with the mesh `serial_mesh` builds. `serial_mesh` runs only on the
  /// first rank of each group, on an empty serial triangulation; it may throw
  /// std::invalid_argument (a bad file, a missing mesh), which is thrown on every rank.
  /// `group_size` 0: one group per compute node (MPI_COMM_TYPE_SHARED). With `balanced`, the
  /// partition gives every rank an equal share of the marked cells as well as of all cells
  /// (partition_with_two_balances). `after_partition`, where given, runs on the partitioned serial
  /// mesh of each group root.
  template <int dim>
  void create_distributed_mesh(dealii::parallel::fullydistributed::Triangulation<dim>& tria,
                               const std::function<void(dealii::Triangulation<dim>&)>& serial_mesh,
                               unsigned int group_size = 0, const CellMarker<dim>& balanced = {},
                               const PartitionHook<dim>& after_partition = {});

  /// `create_distributed_mesh` of the gmsh mesh `file` (.geo meshed with `gmsh`'s refinement and
  /// variables, or .msh), refined `global_refinements` times before it is partitioned.
  template <int dim>
  void read_distributed_mesh(const std::string& file, const GmshSource& gmsh, int global_refinements,
                             const std::string&                                      work_directory,
                             dealii::parallel::fullydistributed::Triangulation<dim>& tria,
                             const CellMarker<dim>&                                  balanced = {});

  /// Sets the subdomain ids of the active cells of `tria` to `n_parts` parts by METIS on the
  /// cells' face graph (short interfaces). Without `marked` (or with fewer marked cells than
  /// parts) the parts have equal numbers of cells within 3 % (which lets a cut follow a layer of
  /// cells; METIS's bisection alone would balance to 0.1 % with a jagged cut). With it, METIS's
  /// multi-constraint partitioning (Karypis & Kumar, SC'98) balances two weights at once, 1 per cell and 1
  /// per marked cell, so that every part also gets its share of the marked cells: a single weight per cell
  /// can only balance a sum (a part with the whole contact surface and fewer volume cells has the same sum as
  /// one with none), which leaves the surface on one rank whenever a cut through the volume is shorter than
  /// one through the surface. Returns the number of marked cells in each part.
  template <int dim>
  std::vector<unsigned int> partition_with_two_balances(dealii::Triangulation<dim>& tria,
                                                        unsigned int n_parts, const CellMarker<dim>& marked);

  /// Dirichlet constraints u = g on the faces with boundary id `id` (components in `mask`),
  /// for the locally owned DOFs only. A fully distributed triangulation stores no cell beyond
  /// the ghost layer, so the outer faces of ghost cells look like boundary faces (with boundary
  /// id 0): deal.II's interpolate_boundary_values, which visits ghost cells too, would constrain
  /// the ghost DOFs there. An owned DOF sees every face through its vertex correctly (all cells
  /// at it are owned or ghosts); close_distributed_constraints() then gives the ghost DOFs their
  /// owners' constraints.
  template <int dim>
  void add_boundary_constraints(const dealii::DoFHandler<dim>& dof_handler, dealii::types::boundary_id id,
                                const dealii::Function<dim>& g, dealii::AffineConstraints<double>& constraints,
                                const dealii::ComponentMask& mask = {});

  /// Gives every DOF of `known` (the locally relevant ones, and any further ones this rank reads,
  /// such as a contact surface's; `constraints` must have been reinit'ed with it) the constraints
  /// of its owner, and closes them.
  template <int dim>
  void close_distributed_constraints(const dealii::DoFHandler<dim>& dof_handler, const dealii::IndexSet& known,
                                     dealii::AffineConstraints<double>& constraints);

  /// Reference positions of the vertices whose first DOF (component 0) is locally owned and
  /// accepted by `keep`, node-major (dim numbers per vertex) in ascending DOF order: the order of
  /// a BlockSystem block's nodes when its rows are the owned DOFs in ascending order (the
  /// rigid-body modes and the nodal coordinates of the AMG).
  template <int dim>
  std::vector<double> owned_vertex_positions(
      const dealii::DoFHandler<dim>& dof_handler, const dealii::IndexSet& owned,
      const std::function<bool(dealii::types::global_dof_index)>& keep = [](dealii::types::global_dof_index) {
        return true;
      });
} // namespace physics
