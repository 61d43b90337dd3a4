// CondensedFsi (condensed_fsi_problem.h): the meshes, the fields, the interface maps and the
// Newton system of the condensed formulation.
#include "fsi/condensed_fsi_problem.h"

#include "common/distributed_mesh.h"
#include "common/row_exchange.h"
#include "common/tpetra_bridge.h"
#include "fsi/interface_nodes.h"

#include <Xpetra_MultiVectorFactory.hpp>

#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>

namespace physics::fsi
{
  using namespace dealii;
  using multigrid::GO;

  template <int dim>
  CondensedFsi<dim>::CondensedFsi(const FsiParameters& p, MPI_Comm comm)
      : p_(p)
      , comm_(comm)
      , rank_(Utilities::MPI::this_mpi_process(comm))
      , pcout_(std::cout, rank_ == 0)
      , timer_(pcout_, TimerOutput::never, TimerOutput::wall_times)
      , fluid_tria_(comm)
      , solid_tria_(comm)
      , fluid_fe_(FE_Q<dim>(1), dim + 1)
      , vector_fe_(FE_Q<dim>(1), dim)
      , fluid_dofs_(fluid_tria_)
      , mesh_dofs_(fluid_tria_)
      , solid_dofs_(solid_tria_)
  {
  }

  template <int dim>
  void CondensedFsi<dim>::make_meshes()
  {
    // Both meshes fully distributed: built by the group roots, partitioned by METIS each on its
    // own (common/distributed_mesh.h), so a rank stores only its cells and their ghost layer.
    if (!p_.mesh_file.empty())
      read_fsi_meshes<dim>(p_.mesh_file, p_.gmsh_source(), p_.global_refinements, p_.output_directory,
                           fluid_tria_, solid_tria_);
    else if constexpr (dim == 2)
      make_channel_meshes({p_.length, p_.height, p_.wall_thickness, static_cast<unsigned>(p_.cells_x),
                           static_cast<unsigned>(p_.cells_fluid_y), static_cast<unsigned>(p_.cells_wall_y),
                           static_cast<unsigned>(p_.cells_wall_x)},
                          fluid_tria_, solid_tria_);
    // (dim 3 without a mesh file is refused by FsiParameters::parse)
    // The fluid's bounding box (over all ranks): its size sets the tolerance of node matching,
    // its centre line (along x) the outward direction of the walls.
    for (unsigned d = 0; d < dim; ++d)
      {
        double low = std::numeric_limits<double>::max(), high = -low;
        for (const auto& cell : fluid_tria_.active_cell_iterators())
          if (cell->is_locally_owned())
            for (const unsigned v : cell->vertex_indices())
              {
                low  = std::min(low, cell->vertex(v)[d]);
                high = std::max(high, cell->vertex(v)[d]);
              }
        fluid_low_[d]  = Utilities::MPI::min(low, comm_);
        fluid_high_[d] = Utilities::MPI::max(high, comm_);
      }
    geometry_tolerance_ = 1e-9 * fluid_low_.distance(fluid_high_);
  }

  template <int dim>
  void CondensedFsi<dim>::setup_fields()
  {
    fluid_dofs_.distribute_dofs(fluid_fe_);
    mesh_dofs_.distribute_dofs(vector_fe_);
    solid_dofs_.distribute_dofs(vector_fe_);
    auto index_sets = [](const DoFHandler<dim>& dofs, IndexSet& owned, IndexSet& relevant) {
      owned = dofs.locally_owned_dofs();
      DoFTools::extract_locally_relevant_dofs(dofs, relevant);
    };
    index_sets(fluid_dofs_, fluid_owned_, fluid_relevant_);
    index_sets(mesh_dofs_, mesh_owned_, mesh_relevant_);
    index_sets(solid_dofs_, solid_owned_, solid_relevant_);
    solid_owned_per_rank_ = Utilities::MPI::all_gather(comm_, solid_owned_);
    // The blocks' near-nullspaces and MueLu's node-wise aggregation read a field's DOFs as
    // nodes of consecutive components (deal.II's numbering of a Q1 system without renumbering).
    for (const auto& cell : fluid_dofs_.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned v : cell->vertex_indices())
          for (unsigned c = 0; c <= dim; ++c)
            if (cell->vertex_dof_index(v, c) != cell->vertex_dof_index(v, 0) + c ||
                cell->vertex_dof_index(v, 0) % (dim + 1) != 0)
              throw std::logic_error("fsi: the fluid DOFs are not numbered node by node");
    // Reference coordinates of the owned structure nodes, node-major in DOF order.
    solid_coordinates_ = owned_vertex_positions(solid_dofs_, solid_owned_);

    // Structure: Saint Venant-Kirchhoff, clamped at both ends, generalized-alpha.
    make_boundary_constraints();
    const auto lame           = LameParameters::from_young_poisson(p_.youngs_modulus, p_.poisson_ratio);
    solid_model_.materials[0] = make_material<dim>(p_.law, lame);
    solid_model_.densities[0] = p_.density;
    DynamicSparsityPattern solid_pattern(solid_relevant_);
    DoFTools::make_sparsity_pattern(solid_dofs_, solid_pattern, solid_constraints_, false);
    SparsityTools::distribute_sparsity_pattern(solid_pattern, solid_owned_, comm_, solid_relevant_);
    K_S_.reinit(solid_owned_, solid_owned_, solid_pattern, comm_);
    dynamics_ = std::make_unique<SolidDynamics<dim>>(p_.spectral_radius, p_.time_step, solid_dofs_,
                                                     solid_model_, solid_owned_, solid_relevant_, comm_);

    // Fluid: no-slip on rigid walls and obstacles, the inflow velocity on the inlet when it is
    // prescribed (homogeneous here: the Newton increment; the values are set in begin_step).
    make_fluid_constraints();
    mesh_free_.reinit(mesh_relevant_);
    mesh_free_.close();
    fluid_model_.properties = {p_.fluid_density, p_.fluid_viscosity};
    fluid_model_.scheme     = p_.fluid_scheme;
    fluid_model_.theta      = p_.fluid_theta;
    fluid_model_.tau_with_time_step = p_.tau_with_time_step;
    DynamicSparsityPattern fluid_pattern(fluid_relevant_),
        shape_pattern(fluid_dofs_.n_dofs(), mesh_dofs_.n_dofs(), fluid_relevant_);
    DoFTools::make_sparsity_pattern(fluid_dofs_, fluid_pattern, fluid_constraints_, false);
    SparsityTools::distribute_sparsity_pattern(fluid_pattern, fluid_owned_, comm_, fluid_relevant_);
    K_F_.reinit(fluid_owned_, fluid_owned_, fluid_pattern, comm_);
    std::vector<types::global_dof_index> fi(fluid_fe_.n_dofs_per_cell()), mi(vector_fe_.n_dofs_per_cell());
    for (const auto& cell : fluid_dofs_.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(fi);
          typename DoFHandler<dim>::active_cell_iterator(&fluid_tria_, cell->level(), cell->index(),
                                                         &mesh_dofs_)
              ->get_dof_indices(mi);
          for (const auto i : fi)
            for (const auto j : mi)
              shape_pattern.add(i, j);
        }
    SparsityTools::distribute_sparsity_pattern(shape_pattern, fluid_owned_, comm_, fluid_relevant_);
    S_F_.reinit(fluid_owned_, mesh_owned_, shape_pattern, comm_);

    mesh_motion_ = std::make_unique<AleMeshMotion<dim>>(
        mesh_dofs_, MeshMotionSettings{p_.ale_poisson_ratio, p_.ale_stiffening}, comm_);
    match_interface();

    // The structure values the owned fluid and ALE interface DOFs read (sync_interface),
    // collected first and added at once.
    std::vector<GlobalIndex> read;
    double                   on_rank = 0;
    for (const auto& [f, row] : fluid_partner_)
      if (fluid_owned_.is_element(f))
        for (const auto& [s, w] : row)
          {
            read.push_back(s);
            on_rank += solid_owned_.is_element(s);
          }
    const double couplings       = Utilities::MPI::sum(static_cast<double>(read.size()), comm_);
    interface_couplings_on_rank_ = couplings > 0 ? Utilities::MPI::sum(on_rank, comm_) / couplings : 1;
    for (const auto& [m, row] : mesh_partner_)
      if (mesh_owned_.is_element(m))
        for (const auto& [s, w] : row)
          read.push_back(s);
    solid_ghosts_ = solid_relevant_;
    add_unsorted_indices(solid_ghosts_, std::move(read));
    for (auto* v : {&d_S_, &d_S_old_, &d_S_older_, &d_S_rate_, &d_S_begin_, &dd_S_})
      v->reinit(solid_owned_, comm_);
    d_S_ghosted_.reinit(solid_owned_, solid_ghosts_, comm_);
    u_interface_ghosted_.reinit(solid_owned_, solid_ghosts_, comm_);
    for (auto* v : {&x_F_, &x_F_old_, &x_F_older_, &x_F_rate_, &x_F_begin_, &dx_F_})
      v->reinit(fluid_owned_, comm_);
    x_F_ghosted_.reinit(fluid_owned_, fluid_relevant_, comm_);
    for (auto* v : {&d_G_, &d_G_old_, &d_G_older_, &d_G_rate_, &d_G_begin_, &dd_G_})
      v->reinit(mesh_owned_, comm_);
    d_G_ghosted_.reinit(mesh_owned_, mesh_relevant_, comm_);
  }

  template <int dim>
  void CondensedFsi<dim>::make_boundary_constraints()
  {
    // On a fully distributed mesh the outer faces of the ghost layer look like boundary faces
    // with id 0 (never an id of this app): the Dirichlet DOFs are found on the owned DOFs only and then given
    // to their ghost copies (common/distributed_mesh.h).
    const Functions::ZeroFunction<dim> zero(dim);
    solid_constraints_.reinit(solid_relevant_);
    AffineConstraints<double> mesh_planes(mesh_relevant_);
    for (const types::boundary_id id :
         {boundary::inlet, boundary::outlet, boundary::wall, boundary::obstacle})
      {
        add_boundary_constraints(solid_dofs_, id, zero, solid_constraints_);
        add_boundary_constraints(mesh_dofs_, id, zero, mesh_planes); // ALE fixed on the planes
      }
    close_distributed_constraints(solid_dofs_, solid_relevant_, solid_constraints_);
    close_distributed_constraints(mesh_dofs_, mesh_relevant_, mesh_planes);
    for (const auto sd : solid_relevant_)
      if (solid_constraints_.is_constrained(sd))
        solid_clamped_.insert(sd);
    for (const auto m : mesh_relevant_)
      if (mesh_planes.is_constrained(m))
        mesh_fixed_.insert(m);
  }

  template <int dim>
  void CondensedFsi<dim>::make_fluid_constraints()
  {
    const Functions::ZeroFunction<dim> zero(dim + 1);
    const ComponentMask                velocity = fluid_fe_.component_mask(FEValuesExtractors::Vector(0));
    fluid_constraints_.reinit(fluid_relevant_);
    for (const types::boundary_id id : {boundary::wall, boundary::obstacle})
      add_boundary_constraints(fluid_dofs_, id, zero, fluid_constraints_, velocity);
    if (p_.parabolic_inflow)
      add_boundary_constraints(fluid_dofs_, boundary::inlet, zero, fluid_constraints_, velocity);
    close_distributed_constraints(fluid_dofs_, fluid_relevant_, fluid_constraints_);
    fluid_free_.reinit(fluid_relevant_);
    fluid_free_.close();
  }

  template <int dim>
  void CondensedFsi<dim>::match_interface()
  {
    // Every rank's owned interface nodes of the three fields, gathered everywhere
    // (interface_nodes.h); fluid velocities and ALE displacements matched to structure nodes,
    // or (dual mortar) the interface faces gathered and P = D^-1 M computed for every fluid
    // interface node (interface_mortar.cc).
    const auto   solid_nodes = gather_interface_nodes(solid_dofs_, dim, on_interface, comm_);
    const double tol         = geometry_tolerance_;
    // The clamped interface DOFs (the walls' end nodes) of every rank: partners of fluid DOFs
    // on ranks whose structure part does not reach them.
    std::vector<GlobalIndex> clamped;
    for (const auto sd : solid_nodes.dofs)
      if (solid_owned_.is_element(sd) && solid_constraints_.is_constrained(sd))
        clamped.push_back(sd);
    for (const auto& part : Utilities::MPI::all_gather(comm_, clamped))
      solid_clamped_.insert(part.begin(), part.end());
    if (p_.dual_mortar)
      {
        const std::string what =
            p_.mesh_file.empty() ? std::string("Mesh") : "Mesh file '" + p_.mesh_file + "'";
        const auto solid = gather_interface_faces(solid_dofs_, dim, on_interface, comm_);
        const auto faces = [&](const DoFHandler<dim>& dofs) {
          return gather_interface_faces(dofs, dim, on_interface, comm_);
        };
        fluid_partner_ = dual_mortar_partners(faces(fluid_dofs_), solid, dim, what);
        mesh_partner_  = dual_mortar_partners(faces(mesh_dofs_), solid, dim, what);
        // The interface's ends: a fluid node at the place of a clamped structure node stays
        // with it, as with matching nodes. Otherwise its P row reaches the free structure nodes
        // beside the clamp, the fluid's corner moves, and the inlet and outlet planes sweep
        // fluid volume that their flux does not see (channel with 30 fluid and 60 wall cells:
        // mass imbalance 2.2e-2 of the inflow instead of 1e-4). The neighbours' dual functions
        // are left as they are (their rows still sum to 1).
        const auto key = [tol](const Point<dim>& x) { return position_key(x, tol); };
        std::map<PositionKey<dim>, std::size_t> clamped_node;
        for (std::size_t k = 0; k < solid_nodes.positions.size(); ++k)
          if (solid_clamped_.count(solid_nodes.dofs[k * dim]) > 0)
            clamped_node[key(solid_nodes.positions[k])] = k;
        for (auto [dofs, partners] :
             {std::pair{&fluid_dofs_, &fluid_partner_}, std::pair{&mesh_dofs_, &mesh_partner_}})
          {
            const auto nodes = gather_interface_nodes(*dofs, dim, on_interface, comm_);
            for (std::size_t k = 0; k < nodes.positions.size(); ++k)
              if (const auto it = clamped_node.find(key(nodes.positions[k])); it != clamped_node.end())
                for (unsigned c = 0; c < dim; ++c)
                  (*partners)[nodes.dofs[k * nodes.components + c]] = {
                      {solid_nodes.dofs[it->second * dim + c], 1.0}};
          }
      }
    else
      {
        const auto node_map = [&](const DoFHandler<dim>& dofs) {
          InterfacePartners partners;
          const auto nodes = gather_interface_nodes(dofs, dim, on_interface, comm_);
          for (const auto& [d, s] : match_interface_nodes(nodes, solid_nodes, tol))
            partners[d] = {{s, 1.0}};
          return partners;
        };
        fluid_partner_ = node_map(fluid_dofs_);
        mesh_partner_  = node_map(mesh_dofs_);
      }
    for (const auto& [m, s] : mesh_partner_) // the interface ALE DOFs follow the structure
      {
        removed_mesh_.push_back(m);
        mesh_fixed_.erase(m);
      }
    // The wall stations: the distinct axial positions of the interface nodes; the owned
    // structure interface nodes with their station and outward normal.
    for (const auto& x : solid_nodes.positions)
      station_x_.push_back(x[0]);
    std::sort(station_x_.begin(), station_x_.end());
    station_x_.erase(std::unique(station_x_.begin(), station_x_.end(),
                                 [tol](double a, double b) { return std::abs(a - b) <= tol; }),
                     station_x_.end());
    station_count_.assign(station_x_.size(), 0);
    const Point<dim> centre((fluid_low_ + fluid_high_) / 2);
    for (std::size_t k = 0; k < solid_nodes.positions.size(); ++k)
      {
        const Point<dim>& x       = solid_nodes.positions[k];
        const auto        station = static_cast<unsigned>(
            std::lower_bound(station_x_.begin(), station_x_.end(), x[0] - tol) - station_x_.begin());
        ++station_count_[station];
        Tensor<1, dim> outward = x - centre;
        outward[0]             = 0;
        if (outward.norm() > tol)
          outward /= outward.norm();
        const GlobalIndex first = solid_nodes.dofs[k * solid_nodes.components];
        if (solid_owned_.is_element(first))
          wall_nodes_.push_back({first, station, outward});
      }

    n_solid_ = solid_dofs_.n_dofs();
    n_fluid_ = fluid_dofs_.n_dofs(); // the interface velocities stay as placeholder rows (assemble)
    n_mesh_  = mesh_dofs_.n_dofs() - removed_mesh_.size();
    for (const auto m : mesh_owned_)
      if (mesh_partner_.count(m) == 0)
        mesh_inner_owned_.push_back(m);
  }

  template <int dim>
  std::pair<int, GlobalIndex> CondensedFsi<dim>::field_dof(GO g) const
  {
    // Owned rows are contiguous per field and rank, in the fields' own order.
    if (g < n_solid_)
      return {0, static_cast<GlobalIndex>(g)};
    if (g < n_solid_ + n_fluid_)
      return {1, static_cast<GlobalIndex>(g - n_solid_)};
    return {2, mesh_inner_owned_.at(g - mesh_gid(mesh_inner_owned_.front()))};
  }

  template <int dim>
  GO CondensedFsi<dim>::fluid_gid(GlobalIndex f) const
  {
    return n_solid_ + static_cast<GO>(f);
  }

  template <int dim>
  GO CondensedFsi<dim>::mesh_gid(GlobalIndex m) const
  {
    const auto before =
        std::lower_bound(removed_mesh_.begin(), removed_mesh_.end(), m) - removed_mesh_.begin();
    return n_solid_ + n_fluid_ + static_cast<GO>(m) - before;
  }

  template <int dim>
  void CondensedFsi<dim>::sync_interface()
  {
    // The kinematic condition u^F_Gamma = d/dt d^S_Gamma through the fluid's time integrator
    // ((a0 d_{n+1} + a1 d_n + a2 d_{n-1}) / dt + a3 r_n, ale_fluid.h), the stencil of the grid
    // velocity: the fluid on the wall moves with the mesh (no flow through the moving wall), so
    // that inflow - outflow = volume change holds for the discrete fluid (record_step logs it).
    fluid_model_.stencil().rate(d_S_, d_S_old_, d_S_older_, d_S_rate_, dynamics_->scheme().time_step(),
                                u_interface_ghosted_);
    d_S_ghosted_ = d_S_;
    // target_i = sum_s P_is source_s for the owned interface DOFs i (P's rows: the partners).
    const auto apply_rows = [](const InterfacePartners& partners, const IndexSet& owned,
                               const TrilinosWrappers::MPI::Vector& source, TrilinosWrappers::MPI::Vector& target) {
      for (const auto& [i, row] : partners)
        if (owned.is_element(i))
          {
            double value = 0;
            for (const auto& [s, w] : row)
              value += w * source[s];
            target[i] = value;
          }
      target.compress(VectorOperation::insert);
    };
    apply_rows(fluid_partner_, fluid_owned_, u_interface_ghosted_, x_F_);
    apply_rows(mesh_partner_, mesh_owned_, d_S_ghosted_, d_G_);
    x_F_ghosted_ = x_F_;
    d_G_ghosted_ = d_G_;
  }

  template <int dim>
  void CondensedFsi<dim>::assemble_fluid(TrilinosWrappers::MPI::Vector& R, TrilinosWrappers::SparseMatrix* K,
                                         TrilinosWrappers::SparseMatrix*  S,
                                         const AffineConstraints<double>* constraints)
  {
    TrilinosWrappers::MPI::Vector old(fluid_owned_, fluid_relevant_, comm_), older(old), rate(old),
        mesh_old(mesh_owned_, mesh_relevant_, comm_), mesh_older(mesh_old), mesh_rate(mesh_old);
    old        = x_F_old_;
    older      = x_F_older_;
    rate       = x_F_rate_;
    mesh_old   = d_G_old_;
    mesh_older = d_G_older_;
    mesh_rate  = d_G_rate_;
    FluidState<dim> state{&x_F_ghosted_, &old, &older, &d_G_ghosted_, &mesh_old, &mesh_older, &rate, &mesh_rate};
    R.reinit(fluid_owned_, comm_);
    if (K != nullptr)
      *K = 0;
    if (S != nullptr)
      *S = 0;
    assemble_ale_fluid<dim>(fluid_dofs_, &mesh_dofs_, fluid_model_, state,
                            constraints != nullptr ? *constraints : fluid_constraints_, R, K, S, &mesh_free_);
  }

  template <int dim>
  multigrid::BlockSystem CondensedFsi<dim>::assemble(std::vector<double>& norms)
  {
    const double w   = dynamics_->scheme().force_weight(); // 1 - af
    const double af  = 1.0 - w;
    const double tau = fluid_model_.stencil().a0 / dynamics_->scheme().time_step(); // du_Gamma/dd_Gamma

    // Structure: w r(d) + c_m M d + h_n, its Jacobian w K + c_m M.
    TrilinosWrappers::MPI::Vector r_S(solid_owned_, comm_), R_F, R_G(mesh_owned_, comm_);
    K_S_ = 0;
    {
      TrilinosWrappers::MPI::Vector ghosted(solid_owned_, solid_relevant_, comm_);
      ghosted = d_S_;
      assemble_solid(solid_dofs_, solid_model_, ghosted, solid_constraints_, r_S, &K_S_,
                     dynamics_->weights());
      r_S += dynamics_->history();
    }
    assemble_fluid(R_F, &K_F_, p_.shape_derivatives ? &S_F_ : nullptr);
    mesh_motion_->stiffness().vmult(R_G, d_G_); // the ALE residual K_G d^G

    // Rows of the merged system: (row gid) -> (column gid -> value), and the right-hand sides.
    RowPieces                     rows;
    std::map<GlobalIndex, double> rhs;
    auto                          solid_free = [&](GlobalIndex sd) { return solid_clamped_.count(sd) == 0; };
    for (const auto sd : solid_owned_)
      {
        std::map<GO, double> entries;
        add_row(
            K_S_, sd, [](GlobalIndex c) { return static_cast<GO>(c); }, entries);
        auto& row = rows[sd];
        for (const auto& [c, v] : entries)
          if (solid_free(c) || c == static_cast<GO>(sd))
            row[c] += v;
        rhs[sd] -= r_S[sd];
        if (const auto it = lambda_old_.find(sd); it != lambda_old_.end() && solid_free(sd))
          rhs[sd] -= af * it->second; // af lambda_n
      }
    // Entry v in the column of an interface DOF goes to the columns of its structure DOFs,
    // times scale and their weights in P (clamped structure DOFs dropped); an entry in any
    // other column goes through `inner`.
    const auto add_column = [&](const InterfacePartners& partners, GlobalIndex c, double v, double scale,
                                auto& row, const auto& inner) {
      if (const auto it = partners.find(c); it != partners.end())
        {
          for (const auto& [s, p] : it->second)
            if (solid_free(s))
              row[s] += scale * p * v;
        }
      else
        inner(c, v);
    };
    // Fluid rows: interface velocity columns become structure columns times tau (u_Gamma =
    // tau P d_Gamma + ...), interface ALE columns structure columns, fixed ALE columns are
    // dropped. An interface velocity row goes to the structure rows of its partners, times
    // (1 - af) P^T. The condensed interface velocity keeps its place in the fluid block as a
    // decoupled placeholder row (1 on the diagonal, no other entry in its row or column,
    // right-hand side 0; update() ignores its increment): so every fluid node has its dim + 1
    // DOFs, and the AMG aggregates the fluid node-wise with the velocity and pressure constants
    // as its near-nullspace.
    for (const auto f : fluid_owned_)
      {
        std::map<GO, double> row, entries;
        add_row(
            K_F_, f, [](GlobalIndex c) { return static_cast<GO>(c); }, entries);
        for (const auto& [c, v] : entries)
          add_column(fluid_partner_, c, v, tau, row,
                     [&](GlobalIndex c, double v) { row[fluid_gid(c)] += v; });
        if (p_.shape_derivatives)
          {
            entries.clear();
            add_row(
                S_F_, f, [](GlobalIndex c) { return static_cast<GO>(c); }, entries);
            for (const auto& [c, v] : entries)
              add_column(mesh_partner_, c, v, 1.0, row, [&](GlobalIndex c, double v) {
                if (mesh_fixed_.count(c) == 0)
                  row[mesh_gid(c)] += v;
              });
          }
        if (!is_interface_velocity(f))
          {
            auto& target = rows[fluid_gid(f)];
            for (const auto& [c, v] : row)
              target[c] += v;
            rhs[fluid_gid(f)] -= R_F[f];
            continue;
          }
        rows[fluid_gid(f)][fluid_gid(f)] = 1.0;
        rhs[fluid_gid(f)]                = 0.0;
        for (const auto& [sd, p] : fluid_partner_.at(f))
          if (solid_free(sd))
            {
              auto& target = rows[sd];
              for (const auto& [c, v] : row)
                target[c] += w * p * v;
              rhs[sd] -= w * p * R_F[f];
            }
      }
    // ALE rows (inner DOFs): fixed planes d^G = 0, elsewhere K_G with the interface columns
    // moved to the structure.
    for (const auto m : mesh_owned_)
      {
        if (mesh_partner_.count(m) > 0)
          continue;
        const GO g   = mesh_gid(m);
        auto&    row = rows[g];
        if (mesh_fixed_.count(m) > 0)
          {
            row[g] = 1.0;
            rhs[g] = 0.0;
            continue;
          }
        std::map<GO, double> entries;
        add_row(
            mesh_motion_->stiffness(), m, [](GlobalIndex c) { return static_cast<GO>(c); }, entries);
        for (const auto& [c, v] : entries)
          add_column(mesh_partner_, c, v, 1.0, row, [&](GlobalIndex c, double v) {
            if (mesh_fixed_.count(c) == 0)
              row[mesh_gid(c)] += v;
          });
        rhs[g] -= R_G[m];
      }
    // Interface rows computed by a fluid rank go to the structure DOF's owner.
    const auto owner = [&](GlobalIndex g) {
      return g < static_cast<GlobalIndex>(n_solid_) ? owning_rank(solid_owned_per_rank_, g) : rank_;
    };
    rows = send_rows_to_owners(std::move(rows), owner, comm_);
    rhs  = send_entries_to_owners(rhs, owner, comm_);

    // Owned rows in ascending order: structure, fluid inner, ALE inner (contiguous per rank).
    std::vector<std::vector<GO>> block_gids(3);
    std::vector<GO>              gids;
    for (const auto& [g, entries] : rows)
      {
        const GO gid = static_cast<GO>(g);
        block_gids[gid < n_solid_ ? 0 : gid < n_solid_ + n_fluid_ ? 1 : 2].push_back(gid);
        gids.push_back(gid);
      }
    auto A = matrix_from_rows(comm_, n_solid_ + n_fluid_ + n_mesh_, rows);
    rows.clear();
    auto b = Xpetra::MultiVectorFactory<double, int, GO, multigrid::NO>::Build(A->getRowMap(), 1, true);
    {
      auto data = b->getDataNonConst(0);
      for (std::size_t i = 0; i < gids.size(); ++i)
        data[i] = rhs.count(gids[i]) > 0 ? rhs.at(gids[i]) : 0.0;
    }
    std::vector<multigrid::BlockInfo> blocks(3);
    blocks[0]   = {"structure", dim, n_solid_, 0, {}, {}, {}};
    blocks[1]   = {"fluid", dim + 1, n_fluid_, 0, {}, {}, {}};
    blocks[2]   = {"ale", dim, n_mesh_, 0, {}, {}, {}};
    auto system = multigrid::BlockSystem::from_merged(teuchos_comm(comm_), blocks, block_gids, A, b);
    // Near-nullspaces: the structure's rigid-body modes, the fluid's constant velocities and
    // pressure, the ALE block's translations (every block node-major, node-complete per rank).
    system.block(0).nullspace = multigrid::rigid_body_modes(system.block(0).map, dim, solid_coordinates_);
    system.block(1).nullspace = multigrid::translation_modes(system.block(1).map, dim + 1);
    system.block(2).nullspace = multigrid::translation_modes(system.block(2).map, dim);
    // Node positions (the aggregates' pictures): every field's owned nodes in DOF order; the ALE
    // block without its interface nodes (condensed into the structure's).
    multigrid::set_node_coordinates(system.block(0), dim, solid_coordinates_);
    multigrid::set_node_coordinates(system.block(1), dim, owned_vertex_positions(fluid_dofs_, fluid_owned_));
    multigrid::set_node_coordinates(system.block(2), dim,
                                    owned_vertex_positions(mesh_dofs_, mesh_owned_, [&](GlobalIndex m) {
                                      return mesh_partner_.count(m) == 0;
                                    }));
    norms                     = system.block_norms(*system.rhs());
    return system;
  }

  template <int dim>
  double CondensedFsi<dim>::ale_residual_scale() const
  {
    TrilinosWrappers::MPI::Vector inner(d_G_), forces(mesh_owned_, comm_);
    for (const auto m : mesh_owned_)
      if (mesh_partner_.count(m) > 0)
        inner[m] = 0.0; // the interface's share is the other side of the balance
    inner.compress(VectorOperation::insert);
    mesh_motion_->stiffness().vmult(forces, inner);
    double squares = 0;
    for (const auto m : mesh_owned_)
      if (mesh_partner_.count(m) == 0 && mesh_fixed_.count(m) == 0)
        squares += forces[m] * forces[m];
    return std::sqrt(Utilities::MPI::sum(squares, comm_));
  }

  template class CondensedFsi<2>;
  template class CondensedFsi<3>;
} // namespace physics::fsi
