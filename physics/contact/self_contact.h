// Self-contact is not handled by the mortar pairs (a body is never paired with itself). This
// check finds it after the fact, so that a run stops instead of letting a body pass through
// itself: 2D, two faces (segments) of the same body that cross without sharing a node.
#pragma once

#include <deal.II/base/types.h>

#include <mpi.h>

#include <array>
#include <string>
#include <vector>

namespace physics::contact
{
  /// A surface segment at its current position: its body, the first DOF of each end node (the
  /// node's identity) and the end positions.
  struct BodySegment
  {
    unsigned int                                    body = 0;
    std::array<dealii::types::global_dof_index, 2> node{};
    std::array<std::array<double, 2>, 2>            x{};
  };

  /// "" or a description (body, position) of the first crossing of two segments of one body that
  /// share no node. R-tree of the segments' boxes: O(n log n), no all-pairs loop.
  std::string find_self_crossing(const std::vector<BodySegment>& segments);

  /// Collective: the segments of the other ranks whose bounding box (of all their `own`
  /// segments) meets this rank's. Two segments that cross have meeting boxes, so a rank that
  /// checks its own segments with these sees every crossing involving one of its own.
  std::vector<BodySegment> exchange_nearby_segments(const std::vector<BodySegment>& own, MPI_Comm comm);
} // namespace physics::contact
