// Dual/standard mortar contact, frictionless or with Coulomb friction (coulomb_friction.h), with a
// semi-smooth Newton method (CONTACT.md):
// the contact surfaces of a deal.II mesh, the mortar matrices D and M with their exact
// linearization (Sacado forward AD through common/mortar_integration.h), nodal normals, weighted gaps,
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
//    tangential constraints (constraint_row() says which row holds which). Inactive: lambda_j = 0
//    (identity rows). Active: g~_j = 0 linearized (N row) and, frictionless, tau_j^m . lambda_j = 0
//    linearized (T and F rows); with friction coefficient mu > 0 the tangential rows are the
//    stick or slip rows of coulomb_friction.h (each active node is in the stick or the slip set,
//    updated with the active set), whose slip is measured from set_step_start()'s positions.
//
// Bodies and pairs: in the two-body mode (ContactSettings::surface_boundaries empty) the faces
// with the slave boundary id form the slave surface and those with the master boundary id the
// master surface, and every slave face is integrated against every master face the search finds.
// In the multi-body mode the faces with any of the surface ids are the contact faces of the body
// (material id) of their cell, and a list of pairs (slave body, master body), or the automatic rule
// "every body against every other, the lower body id is the slave", says which bodies meet: ONE
// slave surface (the faces of every body that is slave in at least one pair, one multiplier per
// node) and ONE master surface (the faces of every body that is master in at least one pair), and
// a slave face is integrated only against the master faces of bodies paired with its own body.
// A body may thus be slave toward one neighbour and master toward another (its faces are then in
// both lists; a node may be a slave and a master node). Self-contact is not handled: a body is
// never paired with itself; detect_self_contact() finds faces of one body that cross.
//
// Parallel layout: the volume mesh is fully distributed (common/distributed_mesh.h) and so is the
// slave side. A rank keeps the slave faces of its own cells and those of its ghost cells that
// touch them (the faces around each of its slave nodes, for the nodal normals), the multipliers
// of those nodes, and their contact state. A multiplier lives with its slave node: component c
// of node j has the assembly index n_dofs + (displacement DOF c of j), so the rank owning the
// node's DOFs owns its multiplier and constraint rows, and multipliers travel in vectors of the
// displacement layout (ghosted like the displacements). The nodal sums v_j, w_j of faces on
// different ranks meet at the node's owner (one add-compress) and come back to every rank that
// needs them (one ghost update). Only the master surface is gathered on every rank, once, at
// construction, with the current positions of its nodes (the "redundant master interface" of
// production codes: O(master surface), no volume-sized array). Each rank integrates only the
// slave faces of its locally owned cells and finds master candidates with an R-tree of
// master-face bounding boxes. Rows of nodes owned elsewhere are summed by their owners.
#pragma once

#include <deal.II/base/index_set.h>
#include <deal.II/base/point.h>
#include <deal.II/base/types.h>
#include <deal.II/dofs/dof_handler.h>

#include "contact/contact_pairs.h"

#include <mpi.h>

#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <memory>
#include <set>
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
    /// Multi-body mode: the contact surface ids (empty: the two-body mode of slave/master id).
    std::vector<dealii::types::boundary_id> surface_boundaries;
    /// Multi-body mode: (slave body, master body) pairs of material ids; empty: automatic (every
    /// body with contact faces against every other, the lower id is the slave).
    std::vector<std::pair<unsigned int, unsigned int>> pairs;
    /// Faces only checked for self-contact (e.g. the inner surfaces of rings), never integrated.
    std::vector<dealii::types::boundary_id> watch_boundaries;
    double friction_coefficient = 0.0; ///< Coulomb's mu (0: frictionless)
    double tangential_parameter = 1.0; ///< c_t of the frictional complementarity function
    /// false: slave nodes whose every DOF is constrained never enter the active set (4C's
    /// "RemoveDBCSlaveNodes"); true: they are slave nodes like the others.
    bool prescribed_nodes_contact = true;
  };

  /// One contact-surface node (a mesh vertex with dim displacement DOFs).
  template <int dim>
  struct SurfaceNode
  {
    std::array<global_dof_index, dim> dofs;
    dealii::Point<dim>                reference;
  };

  /// Faces of one side; nodes index into the side's node list, ordered for an outward normal.
  struct SurfaceFaces
  {
    std::vector<std::vector<unsigned int>> nodes;
    std::vector<bool>                      locally_owned; ///< the face's cell is owned here
    std::vector<unsigned int>              body;          ///< material id of the face's cell
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

  /// Per slave node of this rank's list, after a Newton step's evaluation. Valid for the nodes
  /// this rank needs (MortarContact::needs_state: its own slave nodes and the nodes of its own slave
  /// faces); every rank holding such a node has the same values for it.
  struct NodalContactState
  {
    std::vector<bool>   active;
    std::vector<bool>   covered;        ///< has a master face underneath (w_j > 0)
    std::vector<bool>   released;       ///< fully prescribed, kept out of contact (no constraint)
    std::vector<double> weighted_gap;   ///< g~_j
    std::vector<double> weight;         ///< w_j = sum_k D_jk
    std::vector<double> normal_pressure;///< lambda_n,j
    // Friction (mu > 0; frictionless: slip = active, the rest zero)
    std::vector<bool>   slip;           ///< active and sliding (Coulomb bound reached)
    std::vector<double> tangential;     ///< |lambda_tau,j|
    std::vector<double> slip_distance;  ///< |u_j| / w_j: relative slip in the step (length)
    std::vector<double> dissipation;    ///< lambda_tau,j . u_j: energy dissipated in the step
  };

  template <int dim>
  class MortarContact
  {
  public:
    /// Collects this rank's slave faces (own and adjacent ghost cells) and gathers the master
    /// surface from the ranks' own cells (collective); throws std::invalid_argument naming the
    /// missing boundary id if a surface is empty on all ranks.
    MortarContact(const dealii::DoFHandler<dim>& dof_handler, const ContactSettings& settings);

    /// c_n and c_t of the complementarity functions (they need the mesh size, known after
    /// construction).
    void set_complementarity_parameters(double c_n, double c_t)
    {
      settings_.complementarity_parameter = c_n;
      settings_.tangential_parameter      = c_t;
    }
    bool frictional() const { return settings_.friction_coefficient > 0.0; }
    /// Friction: the positions of this rank's slave nodes and of all master nodes at the start of
    /// the step, from which evaluate() measures the slip (unused without friction).
    void set_step_start(const std::vector<std::array<double, dim>>& slave_x,
                        const std::vector<std::array<double, dim>>& master_x)
    {
      slave_start_  = slave_x;
      master_start_ = master_x;
    }

    /// The slave nodes this rank holds (of its own and adjacent ghost slave faces).
    unsigned int n_slave_nodes() const { return slave_nodes_.size(); }
    /// The slave nodes of all ranks (each counted once, by its owner).
    dealii::types::global_dof_index n_global_slave_nodes() const { return n_global_slave_nodes_; }
    const std::vector<SurfaceNode<dim>>& slave_nodes() const { return slave_nodes_; }
    /// Is slave node j (of this rank's list) owned here (its DOFs, multipliers, constraint rows)?
    bool owns_slave_node(unsigned int j) const { return owned_.is_element(slave_nodes_[j].dofs[0]); }
    /// Does this rank compute node j's contact state (it owns j or j lies on one of its faces)?
    bool needs_state(unsigned int j) const { return needs_state_[j]; }
    const std::vector<SurfaceNode<dim>>& master_nodes() const { return master_nodes_; }
    /// Nodes of the faces that are only checked for self-contact (ContactSettings::watch_boundaries).
    const std::vector<SurfaceNode<dim>>& watch_nodes() const { return watch_nodes_; }
    /// Multi-body mode: the bodies that are slave in at least one pair (two-body mode: empty).
    std::set<unsigned int> slave_bodies() const { return pairs_ ? pairs_->slave_bodies() : std::set<unsigned int>{}; }
    /// The pairs in use (multi-body mode; the automatic rule's pairs listed), for the log.
    std::string describe_pairs() const;
    /// Self-contact check: two faces of the same body among the slave, master and watch faces
    /// that cross each other without sharing a node (2D: segments that cross; 3D: an edge of one
    /// through the other, self_contact.h). Collective: each rank checks its own slave and watch
    /// faces, those of the ranks whose faces' bounding box meets theirs (sent point to point) and
    /// the master surface. Returns, on every rank, "" or a description of a crossing (body and
    /// position; the lowest rank's find).
    std::string detect_self_contact(const std::vector<std::array<double, dim>>& slave_x,
                                    const std::vector<std::array<double, dim>>& master_x,
                                    const std::vector<std::array<double, dim>>& watch_x) const;
    /// The DOFs of the master surface and of this rank's slave and watch nodes (the rank needs
    /// their current values).
    std::vector<global_dof_index> surface_dofs() const;
    /// Smallest slave face size (for c_n = factor E / h).
    double minimal_slave_face_size() const { return h_min_; }

    /// Evaluates D, M, the gaps and their linearization at the current positions of this rank's
    /// slave nodes and of all master nodes (reference + displacement) and the multipliers
    /// `lambda` (dim per slave node of this rank's list, global Cartesian components). Updates
    /// the active set (semi-smooth Newton) and fills this rank's contributions (collective).
    /// `is_constrained(dof)` marks Dirichlet DOFs: contact entries in their rows and columns are
    /// dropped.
    void evaluate(const std::vector<std::array<double, dim>>& slave_x,
                  const std::vector<std::array<double, dim>>& master_x, const std::vector<double>& lambda,
                  const std::function<bool(global_dof_index)>& is_constrained, ContactContribution& out);

    const NodalContactState& state() const { return state_; }
    /// The next evaluation takes the geometric active-set guess again (as the first one does):
    /// after an evaluation that only looked at the geometry (the initial overlap check).
    void restart_active_set() { first_evaluation_ = true; }
    /// The next evaluation takes the active set from the multipliers and gaps (as every later
    /// one does): a run resumed from a checkpoint, whose multipliers are those of a solve.
    void continue_active_set() { first_evaluation_ = false; }
    /// Multiplier component c of slave node j in assembly numbering: n_dofs + the node's
    /// displacement DOF c (the multiplier lives with its node).
    global_dof_index multiplier_index(unsigned int j, unsigned int c) const { return n_dofs_ + slave_nodes_[j].dofs[c]; }
    /// Row (assembly numbering) of constraint m of slave node j: m = 0 normal, m > 0 tangential.
    global_dof_index constraint_row(unsigned int j, int m) const
    {
      return multiplier_index(j, constraint_row_[j][m]);
    }
    /// Averaged unit normal at slave node j (from the last evaluation).
    const std::array<double, dim>& normal(unsigned int j) const { return normals_[j]; }

  private:
    /// v_j (dim) and w_j of this rank's faces summed over all ranks' faces at every node this
    /// rank holds (partial: dim + 1 values per node of slave_nodes_).
    /// Generalized: per node `n_vectors` dim-vectors followed by w_j (v_j, and with friction
    /// v_j^start as well).
    std::vector<double> sum_over_ranks(const std::vector<double>& partial, int n_vectors) const;
    /// The tangential rows of the active slave node j with friction (coulomb_friction.h): the
    /// owner adds the residual and the derivatives with respect to lambda_j and the nodal frame,
    /// every rank the derivatives through its partial sums `dslip`, `dw` of v_j - v_j^start and w_j.
    void add_friction_rows(unsigned int j, const std::vector<std::array<double, dim>>& slave_x,
                           const std::vector<double>& lambda, const std::vector<double>& total,
                           const std::map<global_dof_index, std::array<double, dim>>& dslip,
                           const std::map<global_dof_index, double>& dw,
                           const std::function<bool(global_dof_index)>& free_dof, ContactContribution& out);
    /// The slave nodes of the faces around node j, each once: what its nodal frame depends on.
    std::vector<unsigned int> frame_nodes(unsigned int j) const
    {
      std::vector<unsigned int> nodes;
      for (unsigned int f : slave_node_faces_[j])
        for (unsigned int k : slave_faces_.nodes[f])
          if (std::find(nodes.begin(), nodes.end(), k) == nodes.end())
            nodes.push_back(k);
      return nodes;
    }
    /// After the slave faces are collected: which nodes need a state (own nodes, nodes of own
    /// faces: `touched`), the faces around each node in a rank-independent order, h_min.
    void finish_slave_side(const std::set<global_dof_index>& touched);

    ContactSettings               settings_;
    MPI_Comm                      comm_;
    dealii::IndexSet              owned_, relevant_; ///< this rank's owned and relevant DOFs
    global_dof_index              n_global_slave_nodes_ = 0;
    std::vector<bool>             needs_state_;
    std::unique_ptr<ContactPairs> pairs_; ///< multi-body mode only
    std::vector<SurfaceNode<dim>> watch_nodes_;
    SurfaceFaces                  watch_faces_;
    global_dof_index              n_dofs_ = 0;
    std::vector<SurfaceNode<dim>> slave_nodes_, master_nodes_;
    SurfaceFaces                  slave_faces_, master_faces_;
    std::vector<std::vector<unsigned int>> slave_node_faces_; ///< faces adjacent to each slave node
    NodalContactState                      state_;
    std::vector<std::array<double, dim>>   normals_;
    bool                                   first_evaluation_ = true;
    double                                 h_min_            = 0; ///< smallest slave edge (reference)
    std::vector<std::array<int, dim>>      constraint_row_; ///< component row of each constraint
    std::vector<std::array<double, dim>>   slave_start_, master_start_; ///< friction: step start
  };
} // namespace physics::contact
