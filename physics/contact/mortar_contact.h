// Frictionless dual/standard mortar contact with a semi-smooth Newton method (CONTACT.md):
// the contact surfaces of a deal.II mesh, the mortar matrices D and M with their exact
// linearization (Sacado forward AD through mortar_integration.h), nodal normals, weighted gaps,
// the active set and the contact rows and columns of the Newton system.
//
// Conventions (checked by the patch tests in tests/test_contact.cc):
//  - n_j is the averaged OUTWARD unit normal of the slave body at slave node j.
//  - The vector multiplier lambda_j lives on slave node j; the structural residual gets
//        slave rows  + sum_j D_jk lambda_j,   master rows  - sum_j M_jl lambda_j,
//    so the traction on the slave body is -lambda: lambda_n,j = n_j . lambda_j > 0 is the contact
//    PRESSURE (compression positive).
//  - Weighted gap g~_j = n_j . v_j, v_j = sum_l M_jl x_l - sum_k D_jk x_k (current positions):
//    g~_j >= 0 when the bodies are apart.
//  - Complementarity C_j = lambda_n,j - max(0, lambda_n,j - c_n g~_j / w_j) with the nodal weight
//    w_j = sum_k D_jk (> 0), so that c_n carries units of stiffness per length (E/h).
//    Active A = {j : lambda_n,j - c_n g~_j / w_j > 0}, inactive I = the rest.
//  - Multiplier rows of slave node j hold, in the node's own frame, one normal and dim-1
//    tangential constraints (constraint_row() says which row holds which). Inactive: lambda_j = 0 (identity rows). Active: g~_j = 0 linearized (N row) and
//    tau_j^m . lambda_j = 0 linearized (T and F rows).
//
// Parallel layout: the volume mesh is fully distributed (common/distributed_mesh.h); the two
// contact surfaces are gathered from the ranks' own cells once, at construction, and kept on every
// rank with the current positions of their nodes and the multipliers (the "redundant interface"
// of production codes: O(surface) data, no volume-sized array). Each rank integrates only the
// slave faces of its locally owned cells and finds master candidates with an R-tree of
// master-face bounding boxes. Rows of nodes owned elsewhere are summed by the distributed
// matrix/vector (nonlocal adds).
#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/types.h>
#include <deal.II/dofs/dof_handler.h>

#include <mpi.h>

#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace physics::contact
{
  using dealii::types::global_dof_index;

  struct ContactSettings
  {
    dealii::types::boundary_id slave_boundary  = 1;
    dealii::types::boundary_id master_boundary = 2;
    bool                       dual            = true;
    double                     complementarity_parameter = 1.0; ///< c_n (stiffness / length)
    double                     search_radius_factor      = 1.0; ///< bounding boxes grow by this x face size
  };

  /// One contact-surface node (a mesh vertex with dim displacement DOFs).
  template <int dim>
  struct SurfaceNode
  {
    std::array<global_dof_index, dim> dofs;
    dealii::Point<dim>                reference;
    unsigned int                      owner = 0; ///< rank owning the node's DOFs
  };

  /// Faces of one side; nodes index into the side's node list, ordered for an outward normal.
  struct SurfaceFaces
  {
    std::vector<std::vector<unsigned int>> nodes;
    std::vector<bool>                      locally_owned; ///< the face's cell is owned here
  };

  /// A sparse row piece: column (assembly numbering) -> value.
  using SparseRow = std::map<global_dof_index, double>;

  /// What one Newton step's contact evaluation produces, in "assembly numbering": displacement
  /// DOFs keep deal.II's numbers, multiplier (j, c) is n_dofs + dim * j + c.
  struct ContactContribution
  {
    /// Structural residual contributions (slave: D^T lambda, master: -M^T lambda), by DOF.
    std::map<global_dof_index, double> residual;
    /// Matrix entries row -> row piece (displacement rows: K and B^T parts; multiplier rows).
    std::map<global_dof_index, SparseRow> matrix;
    /// Multiplier-row residuals (only for nodes owned by this rank).
    std::map<global_dof_index, double> constraint_residual;
  };

  /// Per slave node, after a Newton step's evaluation (identical on every rank).
  struct NodalContactState
  {
    std::vector<bool>   active;
    std::vector<bool>   covered;        ///< has a master face underneath (w_j > 0)
    std::vector<double> weighted_gap;   ///< g~_j
    std::vector<double> weight;         ///< w_j = sum_k D_jk
    std::vector<double> normal_pressure;///< lambda_n,j
  };

  template <int dim>
  class MortarContact
  {
  public:
    /// Gathers both surfaces from the ranks' own cells (collective); throws
    /// std::invalid_argument naming the missing boundary id if a surface is empty.
    MortarContact(const dealii::DoFHandler<dim>& dof_handler, const ContactSettings& settings);

    /// c_n of the complementarity function (it needs the mesh size, known after construction).
    void set_complementarity_parameter(double c_n) { settings_.complementarity_parameter = c_n; }

    unsigned int n_slave_nodes() const { return slave_nodes_.size(); }
    const std::vector<SurfaceNode<dim>>& slave_nodes() const { return slave_nodes_; }
    const std::vector<SurfaceNode<dim>>& master_nodes() const { return master_nodes_; }
    /// All DOFs of both surfaces (every rank needs their current values).
    std::vector<global_dof_index> surface_dofs() const;
    /// Smallest slave face size (for c_n = factor E / h).
    double minimal_slave_face_size() const { return h_min_; }

    /// Evaluates D, M, the gaps and their linearization at the current positions of all slave
    /// and master nodes (reference + displacement, the same on every rank) and the multipliers
    /// `lambda` (dim per slave node, global Cartesian components). Updates the active set
    /// (semi-smooth Newton) and fills this rank's contributions. `is_constrained(dof)` marks
    /// Dirichlet DOFs: contact entries in their rows and columns are dropped.
    void evaluate(const std::vector<std::array<double, dim>>& slave_x,
                  const std::vector<std::array<double, dim>>& master_x, const std::vector<double>& lambda,
                  const std::function<bool(global_dof_index)>& is_constrained, MPI_Comm comm,
                  ContactContribution& out);

    const NodalContactState& state() const { return state_; }
    /// Multiplier component c of slave node j in assembly numbering.
    global_dof_index multiplier_index(unsigned int j, unsigned int c) const { return n_dofs_ + dim * j + c; }
    /// Row (assembly numbering) of constraint m of slave node j: m = 0 normal, m > 0 tangential.
    global_dof_index constraint_row(unsigned int j, int m) const
    {
      return multiplier_index(j, constraint_row_[j][m]);
    }
    /// Averaged unit normal at slave node j (from the last evaluation).
    const std::array<double, dim>& normal(unsigned int j) const { return normals_[j]; }

  private:
    ContactSettings               settings_;
    global_dof_index              n_dofs_ = 0;
    std::vector<SurfaceNode<dim>> slave_nodes_, master_nodes_;
    SurfaceFaces                  slave_faces_, master_faces_;
    std::vector<std::vector<unsigned int>> slave_node_faces_; ///< faces adjacent to each slave node
    NodalContactState                      state_;
    std::vector<std::array<double, dim>>   normals_;
    bool                                   first_evaluation_ = true;
    double                                 h_min_            = 0; ///< smallest slave edge (reference)
    std::vector<std::array<int, dim>>      constraint_row_; ///< component row of each constraint
  };
} // namespace physics::contact
