// The FSI interface on fully distributed triangulations: matching nodes here, non-matching
// meshes by dual mortar (the faces and P = D^-1 M below, interface_mortar.cc). The fluid and the
// structure are partitioned independently, so the fluid and structure cells at a piece of the
// interface usually live on different ranks, and no rank stores the other field's cells there.
// Each rank therefore contributes the interface nodes (or faces) it owns (reference position and
// DOF indices), and one all-gather gives every rank the whole interface: O(interface) data per
// rank, the surface-sized exception production codes make too (a rank needs the partner of
// every interface DOF it assembles, and the merged numbering needs every rank's count of
// condensed DOFs). Nothing of global size (cells, DOFs) is gathered.
#pragma once

#include "common/row_exchange.h"

#include <deal.II/base/point.h>
#include <deal.II/dofs/dof_handler.h>

#include <mpi.h>

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace physics::fsi
{
  /// A point's coordinates in units of `tolerance` (far below any cell size): the fluid and the
  /// structure mesh generate their interface from the same coordinates, so the same node (or face
  /// centre) of the two gets the same key in a std::map.
  template <int dim>
  using PositionKey = std::array<long long, dim>;

  template <int dim>
  PositionKey<dim> position_key(const dealii::Point<dim>& x, double tolerance)
  {
    PositionKey<dim> k;
    for (unsigned int d = 0; d < dim; ++d)
      k[d] = std::llround(x[d] / tolerance);
    return k;
  }

  /// One field's interface nodes of all ranks: node k at `positions[k]` carries the DOFs
  /// dofs[k * components], ..., dofs[k * components + components - 1] (its first components).
  template <int dim>
  struct InterfaceNodes
  {
    unsigned int                    components = 0;
    std::vector<dealii::Point<dim>> positions;
    std::vector<GlobalIndex>        dofs;
  };

  /// Collective: the vertices of faces with `on_interface(boundary id)` whose DOFs this rank
  /// owns, gathered from every rank. Faces of ghost cells are visited too (an owned vertex may
  /// lie on an interface face of a ghost cell only); the outer faces of the ghost layer carry
  /// boundary id 0, which is never an interface id.
  template <int dim>
  InterfaceNodes<dim>
  gather_interface_nodes(const dealii::DoFHandler<dim>& dofs, unsigned int components,
                         const std::function<bool(dealii::types::boundary_id)>& on_interface, MPI_Comm comm);

  /// DOF of `from` -> DOF of `to` at the same position (coordinates equal to `tolerance`), one
  /// pair per component. Throws std::invalid_argument (the same on every rank, since the input
  /// is) when a node of `from` has no node of `to`: the interface meshes must match.
  template <int dim>
  std::map<GlobalIndex, GlobalIndex> match_interface_nodes(const InterfaceNodes<dim>& from,
                                                           const InterfaceNodes<dim>& to, double tolerance);

  /// How an interface DOF follows the structure: DOF -> (structure DOF, weight) pairs, the row
  /// of P in u_Gamma = P d_Gamma (matching nodes: one pair of weight 1).
  using InterfacePartners = std::map<GlobalIndex, std::vector<std::pair<GlobalIndex, double>>>;

  /// One field's interface faces of all ranks (interface_mortar.cc): the nodes of every face,
  /// each node once (its first `components` DOFs), and per face its node numbers, ordered so
  /// that the right-hand rule gives the field's outward normal (common/mortar_integration.h).
  template <int dim>
  struct InterfaceFaces
  {
    InterfaceNodes<dim>                    nodes;
    std::vector<std::vector<unsigned int>> faces;
  };

  /// Collective: the faces with `on_interface(boundary id)` of the locally owned cells, gathered
  /// from every rank (O(interface) per rank, like gather_interface_nodes).
  template <int dim>
  InterfaceFaces<dim>
  gather_interface_faces(const dealii::DoFHandler<dim>& dofs, unsigned int components,
                         const std::function<bool(dealii::types::boundary_id)>& on_interface, MPI_Comm comm);

  /// Dual mortar on non-matching interface meshes: with the slave side `from` (the fluid) and
  /// the master side `to` (the structure), D_jj and M_jl integrated over the faces' overlaps
  /// with the dual (biorthogonal) multiplier basis of the slave faces, P = D^-1 M row by row (D
  /// is diagonal: no solve), for the first `components` DOFs of every slave node. On matching
  /// meshes P is the node map. Throws std::invalid_argument (the same on every rank) naming
  /// `what` when a slave node does not face the master surface (a row sum of P off 1 by more
  /// than 1e-3: the two interface surfaces do not overlap there).
  template <int dim>
  InterfacePartners dual_mortar_partners(const InterfaceFaces<dim>& from, const InterfaceFaces<dim>& to,
                                         unsigned int components, const std::string& what);
} // namespace physics::fsi
