#include "fsi/fluid_flow.h"

#include "common/distributed_mesh.h"
#include "common/tpetra_bridge.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/vector_tools.h>

#include <cmath>
#include <stdexcept>

namespace physics::fsi
{
  using namespace dealii;

  template <int dim>
  FluidFlow<dim>::FluidFlow(const Triangulation<dim>& tria, FluidFlowSetup<dim> setup, MPI_Comm comm)
      : s_(std::move(setup))
      , comm_(comm)
      , fe_(FE_Q<dim>(1), dim + 1)
      , mesh_fe_(FE_Q<dim>(1), dim)
      , dofs_(tria)
      , mesh_dofs_(tria)
  {
    s_.model.properties.check();
    setup_dofs();
  }

  template <int dim>
  void FluidFlow<dim>::setup_dofs()
  {
    dofs_.distribute_dofs(fe_);
    mesh_dofs_.distribute_dofs(mesh_fe_);
    owned_ = dofs_.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dofs_, relevant_);
    mesh_owned_ = mesh_dofs_.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(mesh_dofs_, mesh_relevant_);
    // The BlockSystem's strided map needs node-major DOFs: (u_1, ..., u_dim, p) of a vertex
    // consecutive, starting at a multiple of dim + 1 (deal.II's default numbering of Q1 systems).
    for (const auto& cell : dofs_.active_cell_iterators())
      if (!cell->is_artificial())
        for (const unsigned int v : cell->vertex_indices())
          for (unsigned int c = 0; c <= dim; ++c)
            if (cell->vertex_dof_index(v, c) != cell->vertex_dof_index(v, 0) + c ||
                cell->vertex_dof_index(v, 0) % (dim + 1) != 0)
              throw std::runtime_error("fluid DOFs are not numbered node by node");

    // Homogeneous constraints of the Newton increment on the Dirichlet DOFs: found on the owned
    // DOFs and given to their ghost copies, so that a fully distributed mesh (whose ghost layer
    // ends in faces that look like boundary faces) works too (common/distributed_mesh.h).
    constraints_.reinit(relevant_);
    const FEValuesExtractors::Vector velocity(0);
    for (const auto& [id, function] : s_.velocity)
      add_boundary_constraints(dofs_, id, Functions::ZeroFunction<dim>(dim + 1), constraints_,
                               fe_.component_mask(velocity));
    if (s_.pressure_point)
      for (const auto& cell : dofs_.active_cell_iterators())
        if (!cell->is_artificial())
          for (const unsigned int v : cell->vertex_indices())
            if (cell->vertex(v).distance(s_.pressure_point->first) < 1e-10 * cell->diameter())
              {
                const auto dof = cell->vertex_dof_index(v, dim);
                if (owned_.is_element(dof) && !constraints_.is_constrained(dof))
                  constraints_.add_line(dof);
              }
    close_distributed_constraints(dofs_, relevant_, constraints_);

    pressure_dofs_ = IndexSet(owned_.size());
    for (const auto i : owned_)
      if (i % (dim + 1) == dim)
        pressure_dofs_.add_index(i);

    DynamicSparsityPattern pattern(relevant_);
    DoFTools::make_sparsity_pattern(dofs_, pattern, constraints_, false);
    SparsityTools::distribute_sparsity_pattern(pattern, owned_, comm_, relevant_);
    jacobian_.reinit(owned_, owned_, pattern, comm_);

    for (auto* v : {&solution_, &old_, &older_, &rate_, &begin_, &direction_, &residual_})
      v->reinit(owned_, comm_);
    ghosted_.reinit(owned_, relevant_, comm_);
    for (auto* v : {&mesh_, &mesh_old_, &mesh_older_, &mesh_rate_})
      v->reinit(mesh_owned_, mesh_relevant_, comm_);
    if (s_.pseudo_elastic)
      mesh_motion_ = std::make_unique<AleMeshMotion<dim>>(mesh_dofs_, *s_.pseudo_elastic, comm_);
  }

  template <int dim>
  void FluidFlow<dim>::update_ghosts()
  {
    ghosted_ = solution_;
  }

  template <int dim>
  void FluidFlow<dim>::set_initial_state(const Function<dim>& initial)
  {
    VectorTools::interpolate(dofs_, initial, solution_);
    old_   = solution_;
    older_ = solution_;
    update_ghosts();
    if (s_.mesh_motion)
      {
        move_mesh(0.0);
        mesh_old_   = mesh_;
        mesh_older_ = mesh_;
      }
  }

  template <int dim>
  void FluidFlow<dim>::apply_dirichlet(double time)
  {
    // The iterate takes the prescribed values; the increments then stay zero there.
    std::map<types::global_dof_index, double> values;
    const FEValuesExtractors::Vector          velocity(0);
    for (const auto& [id, function] : s_.velocity)
      {
        function->set_time(time);
        VectorTools::interpolate_boundary_values(dofs_, id, *function, values, fe_.component_mask(velocity));
      }
    if (s_.pressure_point)
      {
        s_.pressure_point->second->set_time(time);
        const double p = s_.pressure_point->second->value(s_.pressure_point->first, dim);
        for (const auto& line : constraints_.get_lines())
          if (line.index % (dim + 1) == dim)
            values[line.index] = p;
      }
    for (const auto& [dof, value] : values)
      if (owned_.is_element(dof))
        solution_[dof] = value;
    solution_.compress(VectorOperation::insert);
    update_ghosts();
  }

  template <int dim>
  void FluidFlow<dim>::begin_step(double time, double step)
  {
    begin_ = solution_;
    // (BDF2 needs two steps behind it: its first step is BDF1, see assemble().)
    s_.model.time_step = step;
    if (s_.mesh_motion)
      move_mesh(time);
    apply_dirichlet(time);
  }

  template <int dim>
  void FluidFlow<dim>::move_mesh(double time)
  {
    s_.mesh_motion->set_time(time);
    TrilinosWrappers::MPI::Vector d(mesh_owned_, comm_);
    if (mesh_motion_)
      {
        std::map<types::boundary_id, const Function<dim>*> boundary;
        for (const auto id : dofs_.get_triangulation().get_boundary_ids())
          boundary[id] = s_.mesh_motion.get();
        mesh_motion_->solve(boundary, d);
      }
    else
      VectorTools::interpolate(mesh_dofs_, *s_.mesh_motion, d);
    mesh_ = d;
  }

  template <int dim>
  void FluidFlow<dim>::reset_step()
  {
    solution_ = begin_;
    update_ghosts();
  }

  template <int dim>
  void FluidFlow<dim>::end_step(int /*number*/, double /*time*/)
  {
    // The rates at t_{n+1} (one-step-theta carries them; the BDF stencils ignore them).
    const FluidModel<dim> model   = step_model();
    const TimeStencil     stencil = model.stencil();
    stencil.rate(solution_, old_, older_, rate_, model.time_step, rate_);
    if (s_.mesh_motion)
      stencil.rate(mesh_, mesh_old_, mesh_older_, mesh_rate_, model.time_step, mesh_rate_);
    older_      = old_;
    old_        = solution_;
    mesh_older_ = mesh_old_;
    mesh_old_   = mesh_;
    ++steps_done_;
  }

  template <int dim>
  FluidModel<dim> FluidFlow<dim>::step_model() const
  {
    FluidModel<dim> model = s_.model;
    if (model.scheme == FluidTimeScheme::bdf2 && steps_done_ == 0)
      model.scheme = FluidTimeScheme::bdf1;
    return model;
  }

  template <int dim>
  void FluidFlow<dim>::assemble(bool with_jacobian)
  {
    const FluidModel<dim>         model = step_model();
    TrilinosWrappers::MPI::Vector old_ghosted(owned_, relevant_, comm_),
        older_ghosted(owned_, relevant_, comm_), rate_ghosted(owned_, relevant_, comm_);
    old_ghosted   = old_;
    older_ghosted = older_;
    rate_ghosted  = rate_;
    FluidState<dim> state;
    state.fluid       = &ghosted_;
    state.fluid_old   = &old_ghosted;
    state.fluid_older = &older_ghosted;
    state.fluid_rate  = &rate_ghosted;
    if (s_.mesh_motion)
      {
        state.mesh       = &mesh_;
        state.mesh_old   = &mesh_old_;
        state.mesh_older = &mesh_older_;
        state.mesh_rate  = &mesh_rate_;
      }
    residual_ = 0;
    if (with_jacobian)
      jacobian_ = 0;
    assemble_ale_fluid<dim>(dofs_, s_.mesh_motion ? &mesh_dofs_ : nullptr, model, state, constraints_,
                            residual_, with_jacobian ? &jacobian_ : nullptr);
  }

  template <int dim>
  double FluidFlow<dim>::residual_norm()
  {
    assemble(false);
    return residual_.l2_norm();
  }

  template <int dim>
  multigrid::BlockSystem FluidFlow<dim>::block_system() const
  {
    const auto map = to_xpetra_map(owned_, comm_);
    auto       A   = to_xpetra(jacobian_);
    auto       b   = to_xpetra(residual_, A->getRowMap());
    b->scale(-1.0); // K dx = -R
    std::vector<multigrid::BlockInfo> blocks(1);
    blocks[0].name          = "fluid";
    blocks[0].dofs_per_node = dim + 1;
    blocks[0].global_size   = static_cast<multigrid::GO>(dofs_.n_dofs());
    std::vector<multigrid::GO> gids;
    for (const auto i : owned_)
      gids.push_back(static_cast<multigrid::GO>(i));
    auto system = multigrid::BlockSystem::from_merged(teuchos_comm(comm_), blocks, {gids}, A, b);
    // Near-nullspace: constant velocity components and a constant pressure.
    system.block(0).nullspace = multigrid::translation_modes(system.block(0).map, dim + 1);
    return system;
  }

  template <int dim>
  Linearization FluidFlow<dim>::linearize(int /*iteration*/)
  {
    system_ = multigrid::BlockSystem(); // the last Newton matrix: freed before the next is built
    assemble(true);
    system_ = block_system();
    // Residual per field: momentum rows (velocity DOFs) and continuity rows (pressure DOFs).
    double local[2] = {0, 0};
    for (const auto i : owned_)
      local[pressure_dofs_.is_element(i) ? 1 : 0] += residual_[i] * residual_[i];
    double global[2];
    MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_SUM, comm_);
    Linearization result;
    result.system         = &system_;
    result.residual_norms = {std::sqrt(global[0]), std::sqrt(global[1])};
    return result;
  }

  template <int dim>
  void FluidFlow<dim>::update(const multigrid::MultiVector& dx)
  {
    copy_to_dealii(dx, direction_);
    update_length_ = 0;
    set_update_length(1.0);
  }

  template <int dim>
  void FluidFlow<dim>::set_update_length(double step_length)
  {
    solution_.add(step_length - update_length_, direction_);
    update_length_ = step_length;
    update_ghosts();
  }

  template <int dim>
  FlowErrors FluidFlow<dim>::errors(Function<dim>& exact) const
  {
    const QGauss<dim>                  quadrature(3);
    const ComponentSelectFunction<dim> velocity(std::make_pair(0u, static_cast<unsigned>(dim)), dim + 1);
    const ComponentSelectFunction<dim> pressure(dim, dim + 1);
    const Triangulation<dim>&          tria = dofs_.get_triangulation();
    Vector<float>                      cellwise(tria.n_active_cells());
    auto norm = [&](const ComponentSelectFunction<dim>& mask, VectorTools::NormType type) {
      VectorTools::integrate_difference(dofs_, ghosted_, exact, cellwise, quadrature, type, &mask);
      return VectorTools::compute_global_error(tria, cellwise, type);
    };
    FlowErrors e;
    e.velocity_l2 = norm(velocity, VectorTools::L2_norm);
    e.velocity_h1 = norm(velocity, VectorTools::H1_seminorm);
    // Mean-free pressure error: ||e - mean(e)||^2 = ||e||^2 - (int e)^2 / |Omega|.
    const double p_l2       = norm(pressure, VectorTools::L2_norm);
    const double p_integral = norm(pressure, VectorTools::mean);
    const double volume     = GridTools::volume(tria);
    e.pressure_l2           = std::sqrt(std::max(0.0, p_l2 * p_l2 - p_integral * p_integral / volume));
    return e;
  }

  template class FluidFlow<2>;
  template class FluidFlow<3>;
} // namespace physics::fsi
