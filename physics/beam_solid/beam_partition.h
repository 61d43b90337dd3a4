// Beams distributed with their elements (issue 12: no beam-sized array on a rank).
//
// Ownership. The global beam numbering is that of the whole mesh (the order of read_beam_mesh()
// or of the generated fibre grid): node n has the coupled-system DOFs 6 n .. 6 n + 5, beam DOFs
// come first in the block system, and that order does not depend on the number of ranks. Nodes
// are split into contiguous blocks, [n N / P, (n + 1) N / P) on rank n: the block system's beam
// rows of a rank are then one contiguous range, the same as before the beams were distributed,
// so exported systems and iteration counts compare across versions. An element belongs to the
// owner of its first node (after check_and_set_tangents() oriented the fibres head to tail):
// along a fibre the elements then follow their nodes, so almost every element lives where both
// its nodes live, and only the one element at each cut between two ranks' node blocks reads a
// node of the next rank (the ghost layer). Where the elements lie in space plays no role: the
// coupling sends every element to the ranks whose solid cells it may cross
// (beam_solid_coupling.h), so no partition of the beams needs to follow the solid's.
//
// Storage on a rank: its elements, and the nodes (position, tangent) of its elements and of its
// own node block; nothing of the size of all beams.
#pragma once

#include "beam_solid/kirchhoff_beam.h"

#include <deal.II/base/index_set.h>
#include <deal.II/base/types.h>

#include <mpi.h>

#include <array>
#include <vector>

namespace physics::beam_solid
{
  using BeamIndex = dealii::types::global_dof_index;

  /// This rank's part of a beam mesh. `mesh` holds the stored nodes and elements in a local
  /// numbering (mesh.elements refer to local nodes; its tangents are set).
  struct DistributedBeam
  {
    BeamMesh               mesh;
    std::vector<BeamIndex> node_ids;    ///< global number of each local node, ascending
    std::vector<BeamIndex> element_ids; ///< global number of each local element, ascending
    BeamIndex              n_nodes = 0, n_elements = 0; ///< of all ranks together
    BeamIndex              first_owned = 0, end_owned = 0; ///< this rank's node block
    unsigned int           n_ranks = 1;

    BeamIndex n_dofs() const { return 6 * n_nodes; }
    /// The rank whose node block holds global node n.
    unsigned int owner(BeamIndex n) const
    {
      return static_cast<unsigned int>(((n + 1) * n_ranks - 1) / n_nodes);
    }
    bool owns(BeamIndex n) const { return n >= first_owned && n < end_owned; }
    /// Local number of a stored global node; throws std::logic_error if it is not stored here.
    std::size_t local_node(BeamIndex n) const;
    /// Global node of local element e's end a (0, 1).
    BeamIndex global_node(std::size_t e, int a) const { return node_ids[mesh.elements[e][a]]; }
    /// The beam DOFs of the owned nodes, and of every stored node.
    dealii::IndexSet owned_dofs() const;
    dealii::IndexSet stored_dofs() const;
  };

  /// An empty part of a beam mesh of n_nodes nodes and n_elements elements for `rank` of
  /// `n_ranks`: the counts and the node block set, nothing stored yet.
  DistributedBeam empty_part(BeamIndex n_nodes, BeamIndex n_elements, unsigned int rank, unsigned int n_ranks);

  /// Adds to `part` its share of `piece` (checked, tangents set): whole fibres whose nodes and
  /// elements are the global nodes node_offset + i and elements element_offset + e, following
  /// what `part` stored before (global numbers ascending). Its share: the elements whose first
  /// node it owns, their nodes and its own nodes.
  void add_share(const BeamMesh& piece, BeamIndex node_offset, BeamIndex element_offset, DistributedBeam& part);

  /// Distributes `whole` (checked, tangents set; read only on rank 0, ignored elsewhere) among
  /// the ranks of `comm` as described above (collective). Rank 0 holds the whole mesh and every
  /// rank's part only until the parts are sent, during setup; afterwards no rank stores more
  /// than its own part.
  DistributedBeam distribute_beam(const BeamMesh& whole, MPI_Comm comm);

  /// The cells of the solid box [0, size] (cells[d] equal hexahedra along axis d) that beam
  /// elements cross. The coupling integrates over exactly these cells (beam_solid_coupling.h),
  /// and their solid rows are the dense ones of the preconditioner's Schur complement
  /// S = K_SS - K_SB Â K_BS: a rank with more of them does more coupling work and holds a larger
  /// S. Marked on a group root from the whole beam mesh, so that the partition can give every
  /// rank its share of them (common/distributed_mesh.h); one flag per cell of the box.
  class CrossedCells
  {
  public:
    CrossedCells(const std::vector<double>& size, const std::vector<int>& cells);
    /// Marks the cells the elements of `mesh` cross: each element's chord (the reference fibres
    /// are straight) sampled at a quarter of the smallest cell width; a sample on a face marks
    /// the cells on both sides. Points outside the box mark nothing (read_beam_mesh's caller
    /// reports those).
    void mark(const BeamMesh& mesh);
    /// Is the cell with centre `centre` marked?
    bool        contains(const dealii::Point<3>& centre) const;
    std::size_t n_marked() const;

  private:
    /// Position of cell (i, j, k) in flags_.
    std::size_t index(int i, int j, int k) const
    {
      return static_cast<std::size_t>(i) +
             static_cast<std::size_t>(cells_[0]) *
                 (static_cast<std::size_t>(j) + static_cast<std::size_t>(cells_[1]) * k);
    }

    std::array<double, 3> size_;
    std::array<int, 3>    cells_;
    std::vector<char>     flags_; ///< one per cell, at index(i, j, k)
  };
} // namespace physics::beam_solid
