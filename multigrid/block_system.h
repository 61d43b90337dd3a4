// BlockSystem: the one value that crosses from the physics layer (or a file) into the block-AMG
// module. It carries what MueLu's blocked factories need: the n x n blocked operator over strided
// maps, the right-hand side, per-block near-nullspaces and coordinates, and for contact/meshtying
// systems the interface data consumed by InterfaceAggregationFactory (dual -> primal node mapping,
// primal interface DOF map) and by the segregated aggregation (a body label per primal DOF).
//
// Numbering convention (Xpetra mode, not Thyra mode): global DOF ids are contiguous per block,
// block k owning [offset_k, offset_k + n_k), offset_0 = 0; within a block DOFs are node-major
// (node i, component d -> offset_k + i * dofs_per_node + d).
#pragma once

#include "types.h"

#include <Xpetra_Map.hpp>
#include <Xpetra_Matrix.hpp>
#include <Xpetra_MultiVector.hpp>
#include <Xpetra_StridedMap.hpp>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace multigrid
{
  /// Description of one field (one block row/column of the operator).
  struct BlockInfo
  {
    std::string           name; ///< e.g. "displacement", "lagrange multiplier"
    int                   dofs_per_node = 1;
    GO                    global_size   = 0;
    GO                    offset        = 0; ///< first global DOF id of the block
    RCP<const StridedMap> map;               ///< owned DOFs of this rank, striding = dofs_per_node
    RCP<MultiVector>      nullspace;         ///< near-nullspace on `map` (may be null: constants)
    RCP<MultiVector>      coordinates;       ///< nodal coordinates on the node map (may be null)
  };

  /// Contact / meshtying interface data. Block 0 is primal (displacements), block 1 dual (multipliers).
  struct InterfaceInfo
  {
    /// Slave-side primal DOFs that carry multipliers (global ids in block 0), owned part.
    RCP<const Map> primal_interface_dofs;
    /// Local dual node id -> local primal node id (on the same rank), as MueLu's
    /// InterfaceAggregationFactory ("node-based" strategy) expects.
    std::map<LO, LO> dual_to_primal_node;
    /// Primal DOFs of one body (the slave body): the segregated aggregation drops every matrix
    /// entry coupling this set to its complement, so no aggregate crosses the contact interface.
    /// Null when the primal block has no such coupling to cut.
    RCP<const Map> segregation_dofs;
    /// Any number of bodies: a body label per owned primal DOF (one column on block 0's map,
    /// integral values >= 0). The segregated aggregation drops every entry that couples two DOFs
    /// with different labels. Null: the two labels of segregation_dofs (1 inside, 0 outside).
    RCP<MultiVector> body_labels;
    /// Optional master / slave body DOF sets (reporting, diagnostics).
    RCP<const Map> master_dofs, slave_dofs;
  };

  class BlockSystem
  {
  public:
    /// Build from a matrix whose row map already follows the block numbering convention.
    /// `owned_block_gids[k]` are this rank's DOFs of block k (ascending, node-complete); the
    /// matrix and the rhs are imported into that distribution if they live elsewhere.
    static BlockSystem from_merged(RCP<const Comm> comm, std::vector<BlockInfo> blocks,
                                   const std::vector<std::vector<GO>>& owned_block_gids,
                                   RCP<Matrix> merged_matrix, RCP<MultiVector> rhs);

    RCP<const Comm>  comm() const { return comm_; }
    std::size_t      n_blocks() const { return blocks_.size(); }
    const BlockInfo& block(std::size_t k) const { return blocks_.at(k); }
    BlockInfo&       block(std::size_t k) { return blocks_.at(k); }
    GO               global_size() const;

    /// Blocked operator (SubBlockAFactory-compatible: strided maps, Xpetra numbering).
    RCP<BlockedCrsMatrix> blocked_matrix() const { return blocked_; }
    /// The same operator as one CrsMatrix on the full map (fast apply for the Krylov method).
    RCP<Matrix>             merged_matrix() const { return merged_; }
    RCP<const Map>          full_map() const;
    RCP<const MapExtractor> map_extractor() const { return extractor_; }
    RCP<MultiVector>        rhs() const { return rhs_; }
    void                    set_rhs(RCP<MultiVector> b) { rhs_ = std::move(b); }

    bool                 has_interface() const { return interface_.has_value(); }
    const InterfaceInfo& interface() const;
    void                 set_interface(InterfaceInfo info);
    /// The body label of every owned primal DOF (block 0's map): InterfaceInfo::body_labels, or
    /// 1 / 0 for DOFs inside / outside segregation_dofs, or all 0 (nothing to cut).
    RCP<MultiVector> segregation_labels() const;

    /// Near-nullspace of block k, or the constant vectors per DOF component when none is stored
    /// (translations: what Lagrange multipliers and ALE fields use).
    RCP<MultiVector> nullspace_or_translations(std::size_t k) const;

    /// Checks: square blocks, finite entries, consistent sizes and interface data. Throws InputError.
    void validate(const std::string& source) const;

    /// ||b_k - (A x)_k|| for every block k.
    std::vector<double> block_residual_norms(const MultiVector& x, const MultiVector& b) const;
    std::vector<double> block_norms(const MultiVector& v) const;

  private:
    RCP<const Comm>              comm_;
    std::vector<BlockInfo>       blocks_;
    RCP<Matrix>                  merged_;
    RCP<BlockedCrsMatrix>        blocked_;
    RCP<const MapExtractor>      extractor_;
    RCP<MultiVector>             rhs_;
    std::optional<InterfaceInfo> interface_;
  };

  /// Rigid-body modes (2D: 2 translations + 1 rotation; 3D: 3 + 3) for DOFs on `map` from nodal
  /// coordinates (node-major, dim components per node; coordinates on the same rank).
  RCP<MultiVector> rigid_body_modes(const RCP<const Map>& dof_map, int dim,
                                    const std::vector<double>& local_node_coordinates);

  /// Sets `block.coordinates` (one column per space dimension on the block's node map: node id =
  /// (DOF id - offset) / dofs_per_node) from this rank's node positions, node-major in the order
  /// of the block's owned DOFs. Throws InputError when the counts do not match.
  void set_node_coordinates(BlockInfo& block, int dim, const std::vector<double>& local_node_coordinates);

  /// Translations only: one constant vector per DOF component.
  RCP<MultiVector> translation_modes(const RCP<const Map>& dof_map, int dofs_per_node);

  /// The same local values on another map with the same local length (e.g. a block's vector on
  /// its zero-based or file-order twin map).
  RCP<MultiVector> with_map(const MultiVector& v, const RCP<const Map>& map);
} // namespace multigrid
