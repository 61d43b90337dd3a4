// CondensedFsi (condensed_fsi_problem.h): the time steps, the Newton updates, the traction
// recovery, the Jacobian check, the output and the run.
#include "common/run_directory.h"
#include "fsi/condensed_fsi_problem.h"

#include <Xpetra_MultiVectorFactory.hpp>

#include <deal.II/base/mpi.h>
#include <deal.II/fe/mapping_q_eulerian.h>
#include <deal.II/numerics/data_out.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>

namespace physics::fsi
{
  using namespace dealii;
  using multigrid::GO;

  template <int dim>
  void CondensedFsi<dim>::check_jacobian()
  {
    // A direction of the fields' scales (displacements 1e-3, fluid 1), zero on the rows whose
    // values are prescribed (clamped structure DOFs, fixed ALE DOFs).
    std::vector<double>    norms;
    multigrid::BlockSystem system = assemble(norms);
    const auto             map    = system.full_map();
    auto v  = Xpetra::MultiVectorFactory<double, int, GO, multigrid::NO>::Build(map, 1, true);
    auto Av = Xpetra::MultiVectorFactory<double, int, GO, multigrid::NO>::Build(map, 1, true);
    {
      auto data = v->getDataNonConst(0);
      for (std::size_t i = 0; i < map->getNodeNumElements(); ++i)
        {
          const GO g              = map->getGlobalElement(i);
          const auto [field, dof] = field_dof(g);
          const bool fixed =
              (field == 0 && solid_constraints_.is_constrained(dof)) ||
              (field == 1 && (is_interface_velocity(dof) || fluid_constraints_.is_constrained(dof))) ||
              (field == 2 && mesh_fixed_.count(dof) > 0);
          data[i] = fixed ? 0.0 : (field == 1 ? 1.0 : 1e-3) * std::sin(1.3 * g + 0.4);
        }
    }
    system.merged_matrix()->apply(*v, *Av);
    const double eps = 1e-5;
    update(*v); // x + v, then scaled by the step length below
    set_update_length(eps);
    auto plus = assemble(norms).rhs();
    set_update_length(-eps);
    auto minus = assemble(norms).rhs();
    set_update_length(0.0);
    // (rhs(-eps) - rhs(+eps)) / (2 eps) = dR/dx v, since rhs = -R.
    minus->update(-1.0 / (2 * eps), *plus, 1.0 / (2 * eps));
    const auto fd = system.block_norms(*minus);
    minus->update(-1.0, *Av, 1.0);
    const auto         error = system.block_norms(*minus), reference = system.block_norms(*Av);
    JsonLinesLog::Line line;
    line.add("event", std::string("jacobian_check"));
    pcout_ << "Jacobian check (central differences, eps = " << eps << "): relative error";
    for (std::size_t k = 0; k < 3; ++k)
      {
        const double relative = error[k] / std::max(reference[k], 1e-300);
        line.add("relative_error_" + field_names()[k], relative);
        pcout_ << " " << field_names()[k] << " " << relative;
      }
    pcout_ << " (|J v| " << reference[0] << ", " << reference[1] << ", " << reference[2] << "; |FD| " << fd[0]
           << ", " << fd[1] << ", " << fd[2] << ")\n";
    if (log_.is_open())
      log_.write(line);
  }

  template <int dim>
  Linearization CondensedFsi<dim>::linearize(int iteration)
  {
    if (p_.check_jacobian && iteration == 0 && steps_done_ == 1)
      check_jacobian();
    Linearization result;
    system_       = multigrid::BlockSystem(); // the last Newton matrix: freed before the next is built
    system_       = assemble(result.residual_norms);
    result.system = &system_;
    // The ALE equations are linear with a zero right-hand side: after the first update their
    // residual is only the linear solve's error, so its own first norm is no reference, and the
    // absolute tolerance alone (a number in the mesh stiffness' units) would decide.
    result.residual_scales = {0.0, 0.0, ale_residual_scale()};
    return result;
  }

  template <int dim>
  void CondensedFsi<dim>::update(const multigrid::MultiVector& dx)
  {
    // Split the merged increment into the fields' owned DOFs.
    dd_S_           = 0;
    dx_F_           = 0;
    dd_G_           = 0;
    const auto data = dx.getData(0);
    const auto map  = dx.getMap();
    for (std::size_t i = 0; i < map->getNodeNumElements(); ++i)
      {
        const auto [field, dof] = field_dof(map->getGlobalElement(i));
        if (field == 1 && is_interface_velocity(dof))
          continue; // a placeholder row: the interface velocity follows the structure
        (field == 0 ? dd_S_ : field == 1 ? dx_F_ : dd_G_)[dof] = data[i];
      }
    dd_S_.compress(VectorOperation::insert);
    dx_F_.compress(VectorOperation::insert);
    dd_G_.compress(VectorOperation::insert);
    update_length_ = 0;
    set_update_length(1.0);
  }

  template <int dim>
  void CondensedFsi<dim>::set_update_length(double step_length)
  {
    const double change = step_length - update_length_;
    d_S_.add(change, dd_S_);
    x_F_.add(change, dx_F_);
    d_G_.add(change, dd_G_);
    update_length_ = step_length;
    sync_interface();
  }

  template <int dim>
  void CondensedFsi<dim>::begin_step(double time, double step)
  {
    d_S_begin_ = d_S_;
    x_F_begin_ = x_F_;
    d_G_begin_ = d_G_;
    dynamics_->set_time_step(step);
    dynamics_->begin_step(d_S_, solid_constraints_);
    d_S_old_               = d_S_;
    fluid_model_.time_step          = step;
    fluid_model_.previous_time_step = last_time_step_; // BDF2's weights on unequal steps
    if (p_.parabolic_inflow)
      apply_inflow(time);
    else
      fluid_model_.boundary_pressures[boundary::inlet] =
          time <= p_.pulse_duration * (1 + 1e-12) ? p_.inlet_pressure : 0.0;
    sync_interface(); // the constant-displacement predictor's interface velocity
  }

  template <int dim>
  void CondensedFsi<dim>::reset_step()
  {
    d_S_ = d_S_begin_;
    x_F_ = x_F_begin_;
    d_G_ = d_G_begin_;
    sync_interface();
  }

  template <int dim>
  void CondensedFsi<dim>::end_step(int number, double time)
  {
    // The converged step's fluid residual, assembled once without constraints and before the
    // states shift below, so that its time derivatives and grid velocity are the step's own. Its
    // interface rows give the interface traction lambda_{n+1} = P^T R^F_Gamma on the structure's
    // interface DOFs (for the next step's af lambda_n term, sent to the owners of the structure
    // DOFs); its obstacle and interface rows give the forces (record_forces). The fluid's
    // constraints are homogeneous Dirichlet conditions only, so an unconstrained row equals the
    // constrained assembly's; the rows those conditions fix are left out of lambda, as the
    // constrained assembly zeroes them.
    TrilinosWrappers::MPI::Vector R_F;
    assemble_fluid(R_F, nullptr, nullptr, &fluid_free_);
    std::map<GlobalIndex, double> lambda;
    for (const auto& [f, row] : fluid_partner_)
      if (fluid_owned_.is_element(f) && !fluid_constraints_.is_constrained(f))
        for (const auto& [sd, p] : row)
          lambda[sd] += p * R_F[f];
    lambda_old_ = send_entries_to_owners(
        lambda, [&](GlobalIndex g) { return owning_rank(solid_owned_per_rank_, g); }, comm_);
    dynamics_->end_step(d_S_);
    // The rates at t_{n+1} before the states shift (one-step-theta's r_n of the next step).
    const TimeStencil stencil = fluid_model_.stencil();
    const double      dt      = fluid_model_.time_step;
    stencil.rate(d_S_, d_S_old_, d_S_older_, d_S_rate_, dt, d_S_rate_);
    stencil.rate(x_F_, x_F_old_, x_F_older_, x_F_rate_, dt, x_F_rate_);
    stencil.rate(d_G_, d_G_old_, d_G_older_, d_G_rate_, dt, d_G_rate_);
    d_S_older_ = d_S_old_;
    x_F_older_ = x_F_old_;
    x_F_old_   = x_F_;
    d_G_older_ = d_G_old_;
    d_G_old_   = d_G_;
    last_time_step_ = fluid_model_.time_step; // BDF2's previous step in the next begin_step
    ++steps_done_;
    record_step(number, time);
    record_forces(number, time, R_F);
  }

  template <int dim>
  void CondensedFsi<dim>::write_output(int number, double time, bool last)
  {
    if (!p_.vtk_due(number, last))
      return;
    TimerOutput::Scope scope(timer_, "output");
    {
      // Fluid on the moved mesh: velocity, pressure, grid displacement, partition.
      MappingQEulerian<dim, TrilinosWrappers::MPI::Vector> moved(1, mesh_dofs_, d_G_ghosted_);
      DataOut<dim>                                         out;
      out.attach_dof_handler(fluid_dofs_);
      std::vector<std::string> names(dim, "velocity");
      names.emplace_back("pressure");
      std::vector<DataComponentInterpretation::DataComponentInterpretation> kinds(
          dim, DataComponentInterpretation::component_is_part_of_vector);
      kinds.push_back(DataComponentInterpretation::component_is_scalar);
      out.add_data_vector(x_F_ghosted_, names, DataOut<dim>::type_dof_data, kinds);
      out.add_data_vector(mesh_dofs_, d_G_ghosted_, std::vector<std::string>(dim, "grid_displacement"),
                          std::vector<DataComponentInterpretation::DataComponentInterpretation>(
                              dim, DataComponentInterpretation::component_is_part_of_vector));
      Vector<float> partition(fluid_tria_.n_active_cells());
      partition = static_cast<float>(rank_);
      out.add_data_vector(partition, "partition");
      out.set_cell_selection([](const typename Triangulation<dim>::cell_iterator& c) {
        return c->is_active() && c->is_locally_owned();
      });
      out.build_patches(moved);
      fluid_vtk_->write(out, number, time);
    }
    {
      TrilinosWrappers::MPI::Vector ghosted(solid_owned_, solid_relevant_, comm_);
      ghosted = d_S_;
      MappingQEulerian<dim, TrilinosWrappers::MPI::Vector> moved(1, solid_dofs_, ghosted);
      DataOut<dim>                                         out;
      out.attach_dof_handler(solid_dofs_);
      SolidOutputFields<dim> fields;
      fields.attach(out, solid_dofs_, solid_model_, ghosted);
      out.build_patches(moved);
      solid_vtk_->write(out, number, time);
    }
  }

  template <int dim>
  FsiRunSummary CondensedFsi<dim>::run()
  {
    {
      TimerOutput::Scope scope(timer_, "setup");
      prepare_output_directory(p_.output_directory, comm_);
      make_meshes();
      setup_fields();
      setup_inflow_and_monitors();
      if (rank_ == 0)
        log_ = JsonLinesLog(p_.output_directory + "/run_log.jsonl");
      fluid_vtk_ = std::make_unique<VtkSeries>(p_.output_directory, "fluid", comm_);
      solid_vtk_ = std::make_unique<VtkSeries>(p_.output_directory, "structure", comm_);
      sync_interface();
      volume_old_ = volume_older_ = fluid_balance().volume;
      if (rank_ == 0 && (has_obstacle_ || !p_.monitor_point.empty()))
        {
          forces_csv_.open(p_.output_directory + "/forces.csv");
          forces_csv_ << forces_csv_header();
        }
      if (rank_ == 0 && !has_obstacle_)
        {
          // The wall profile, one row per converged step: time, then the mean outward wall
          // displacement at each station; the header names the stations' x.
          wall_csv_.open(p_.output_directory + "/wall_displacement.csv");
          wall_csv_ << "time";
          for (const double x : station_x_)
            wall_csv_ << "," << std::setprecision(10) << x;
          wall_csv_ << "\n";
        }
    }
    pcout_ << "fsi: fluid " << fluid_tria_.n_global_active_cells() << " cells (at most "
           << Utilities::MPI::max(fluid_tria_.n_active_cells(), comm_) << " stored on a rank), structure "
           << solid_tria_.n_global_active_cells() << " cells (at most "
           << Utilities::MPI::max(solid_tria_.n_active_cells(), comm_)
           << " stored on a rank); Newton system: structure " << n_solid_ << ", fluid " << n_fluid_
           << ", ALE " << n_mesh_ << " DOFs (" << fluid_partner_.size()
           << " interface velocity DOFs condensed, placeholder rows in the fluid block; "
           << std::round(1000 * interface_couplings_on_rank_) / 10
           << " % of their couplings on one rank), shape derivatives "
           << (p_.shape_derivatives ? "on" : "off") << ", " << Utilities::MPI::n_mpi_processes(comm_)
           << " ranks, preset " << p_.solver.preset << "\n";
    NewtonSettings newton_settings   = p_.solver.newton_settings(field_names());
    p_.set_exports(newton_settings);
    NewtonSolver newton(newton_settings, p_.solver.load_preset(), p_.solver.solve_options(), log_, pcout_,
                        timer_, comm_);
    const StepsResult result =
        run_steps(*this, p_.solver.step_settings(p_.end_time, p_.time_step, p_.output_directory), newton, log_, pcout_);
    FsiRunSummary summary;
    summary.structure_dofs = n_solid_;
    summary.fluid_dofs     = n_fluid_;
    summary.ale_dofs       = n_mesh_;
    summary.record(result);
    summary.max_wall_displacement = max_wall_displacement_;
    summary.structure_l2          = d_S_.l2_norm();
    summary.structure_max         = d_S_.linfty_norm();
    summary.ale_l2                = d_G_.l2_norm();
    summary.fluid_l2              = x_F_.l2_norm();
    summary.max_mass_imbalance    = max_mass_imbalance_;
    summary.obstacle_force        = last_force_;
    summary.monitor_displacement  = last_monitor_;
    if (!result.converged)
      pcout_ << "Newton did not converge in time step " << result.steps + 1 << ": " << result.failure << "\n";
    log_timer_summary(timer_, log_, std::cout, rank_ == 0, comm_);
    return summary;
  }

  FsiRunSummary run_condensed_fsi(const FsiParameters& parameters, MPI_Comm comm)
  {
    return parameters.dimension == 3 ? CondensedFsi<3>(parameters, comm).run()
                                     : CondensedFsi<2>(parameters, comm).run();
  }
  // The class is instantiated once, in condensed_fsi.cc (an explicit instantiation of a class
  // may appear in one file only); here the members this file defines.
#define PHYSICS_FSI_STEP_MEMBERS(dim)                                                            \
  template void          CondensedFsi<dim>::check_jacobian();                                   \
  template Linearization CondensedFsi<dim>::linearize(int);                                     \
  template void          CondensedFsi<dim>::update(const multigrid::MultiVector&);              \
  template void          CondensedFsi<dim>::set_update_length(double);                          \
  template void          CondensedFsi<dim>::begin_step(double, double);                         \
  template void          CondensedFsi<dim>::reset_step();                                       \
  template void          CondensedFsi<dim>::end_step(int, double);                              \
  template void          CondensedFsi<dim>::write_output(int, double, bool);                    \
  template FsiRunSummary CondensedFsi<dim>::run();
  PHYSICS_FSI_STEP_MEMBERS(2)
  PHYSICS_FSI_STEP_MEMBERS(3)
#undef PHYSICS_FSI_STEP_MEMBERS
} // namespace physics::fsi
