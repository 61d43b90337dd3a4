// Self-contact is not handled by the mortar pairs (a body is never paired with itself). This
// check finds it after the fact, so that a run stops instead of letting a body pass through
// itself: two faces of the same body that share no node and cross. 2D: two segments that cross;
// 3D: an edge of one face that passes through the other face (quadrilaterals split into two
// triangles), which is how one part of a closed surface enters another.
#pragma once

#include <deal.II/base/types.h>

#include <mpi.h>

#include <array>
#include <string>
#include <vector>

namespace physics::contact
{
  /// A surface face at its current position: its body, the first DOF of each vertex (the node's
  /// identity) and the vertex positions, in order around the face (2D: the two end points; 3D:
  /// three or four vertices).
  template <int dim>
  struct BodyFacet
  {
    unsigned int                                 body = 0;
    std::vector<dealii::types::global_dof_index> node;
    std::vector<std::array<double, dim>>         x;
  };

  /// "" or a description (body, position) of the first crossing of two faces of one body that
  /// share no node. R-tree of the faces' boxes: O(n log n), no all-pairs loop.
  template <int dim>
  std::string find_self_crossing(const std::vector<BodyFacet<dim>>& facets);

  /// Collective: the faces of the other ranks whose bounding box (of all their `own` faces)
  /// meets this rank's. Two faces that cross have meeting boxes, so a rank that checks its own
  /// faces with these sees every crossing involving one of its own.
  template <int dim>
  std::vector<BodyFacet<dim>> exchange_nearby_facets(const std::vector<BodyFacet<dim>>& own, MPI_Comm comm);
} // namespace physics::contact
