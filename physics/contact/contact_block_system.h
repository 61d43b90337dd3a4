// The Newton system of mortar contact, handed to the block-AMG module as a BlockSystem in the
// seeds' block structure:
//
//   displacement DOFs ordered  N1 | M | I | A | N2      (N1: inner master body, M: master surface,
//                                                        I/A: inactive/active slave nodes,
//                                                        N2: inner slave body)
//   multipliers ordered        lambda_I | lambda_A
//
//            du_N1   du_M    du_I    du_A    du_N2   dl_I     dl_A
//   N1    [ K_N1N1  K_N1M   .       .       .       .        .      ]
//   M     [ K_MN1   K_MM    K_MI    K_MA    .       -M_I^T   -M_A^T ]
//   I     [ .       K_IM    K_II    K_IA    K_IN2   D_II^T   D_AI^T ]
//   A     [ .       K_AM    K_AI    K_AA    K_AN2   D_IA^T   D_AA^T ]  = -r
//   N2    [ .       .       K_N2I   K_N2A   K_N2N2  .        .      ]
//   l_I   [ .       .       .       .       .       I        .      ]  (inactive: lambda = 0)
//   l_A,n [ .       N_M     N_I     N_A     .       .        .      ]  (active, normal)
//   l_A,t [ .       F_M     F_I     F_A     .       .        T      ]  (active, tangential)
//
// With dual multipliers D is diagonal on fully covered slave faces, so D_AI = D_IA = 0 there.
// (K_M* and K_S* include the linearized D^T lambda, M^T lambda terms.) Global ids: class by
// class, and within a class rank by rank, node-major with dim components, so each rank's rows of
// every class are contiguous and the strided maps MueLu needs follow directly.
#pragma once

#include "contact/mortar_contact.h"
#include "common/row_exchange.h"

#include "block_system.h"

#include <deal.II/base/index_set.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <vector>

namespace physics::contact
{
  /// Node classes in the order of the displacement block.
  enum class NodeClass : int
  {
    inner_master = 0,
    master       = 1,
    inactive     = 2,
    active       = 3,
    inner_slave  = 4
  };

  /// A locally owned displacement node.
  template <int dim>
  struct OwnedNode
  {
    std::array<GlobalIndex, dim> dofs;
    std::array<double, dim>      reference{}; ///< reference coordinates
    std::array<double, dim>      position{};  ///< current coordinates (the rigid-body modes' centre)
    bool                         slave_body  = false;
    int                          slave_index = -1; ///< index among the slave surface nodes, or -1
    bool                         master_surface = false;
    int                          body = 0; ///< segregation label: no AMG aggregate holds two bodies' nodes
  };

  /// The assembled Newton system and how its rows map back to the assembly numbering.
  struct ContactLinearSystem
  {
    multigrid::BlockSystem system;
    /// For every local row of the system's full map: the assembly index (deal.II DOF, or
    /// n_dofs + dim * j + c for multiplier (j, c)).
    std::vector<GlobalIndex> assembly_index;
    /// Number of displacement nodes in each class (global), N1, M, I, A, N2, and multiplier nodes.
    std::array<long long, 5> class_sizes{};
  };

  /// Builds the block system. `K` and `residual` are the structural tangent and residual
  /// (deal.II numbering, owned rows); `rows` and `residual_pieces` are the contact contributions
  /// already collected on their owners (assembly numbering); `ghosts` must contain the columns of
  /// `K` (the locally relevant DOFs); the contact rows' columns are looked up wherever they live.
  template <int dim>
  ContactLinearSystem build_contact_system(MPI_Comm comm, const std::vector<OwnedNode<dim>>& nodes,
                                           const MortarContact<dim>& contact, const dealii::IndexSet& owned,
                                           const dealii::IndexSet& ghosts,
                                           const dealii::TrilinosWrappers::SparseMatrix& K,
                                           const dealii::TrilinosWrappers::MPI::Vector& residual,
                                           const RowPieces& rows,
                                           const std::map<GlobalIndex, double>& residual_pieces);
} // namespace physics::contact
