// The state checks, energies and output of the contact problem (contact_problem_class.h): the
// log lines, the final slave-node state of the summary, and the VTK files.
#include "contact/contact_problem_class.h"

#include <deal.II/base/mpi.h>
#include <deal.II/numerics/data_out.h>

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace physics::contact::internal
{
  using namespace dealii;

  template <int dim>
  void ContactProblem<dim>::describe(JsonLinesLog::Line& line, std::ostream& console) const
  {
    line.add("load_factor", load_factor_).add("active", n_active_).add("active_changed", n_changed_);
    console << std::setw(9) << n_active_ << std::setw(9) << n_changed_;
    if (contact_->frictional())
      {
        line.add("slip", n_slip_);
        console << std::setw(9) << n_slip_;
      }
  }

  template <int dim>
  std::string ContactProblem<dim>::checkpoint_kind() const
  {
    std::ostringstream kind;
    kind << "contact " << dim << "D (" << tria_.n_global_active_cells() << " cells, " << dof_handler_.n_dofs()
         << " displacement DOFs, " << contact_->n_global_slave_nodes() << " slave nodes, "
         << (dynamics_ ? "dynamic" : "quasi-static") << ")";
    return kind.str();
  }

  template <int dim>
  void ContactProblem<dim>::save_state(Checkpoint& c) const
  {
    c.store("contact/u", u_);
    c.store("contact/lambda", lambda_);
    if (dynamics_)
      dynamics_->save(c, "contact/dynamics");
    c.store("contact/force_old", contact_force_old_); // this rank's share at t_n (generalized midpoint)
    c.set("contact/time", time_); // the converged step's: the loads of t_n for the next step
    c.set("contact/max_penetration", summary_.max_penetration);
    c.set("contact/active_set_sizes", std::vector<double>(summary_.active_set_sizes.begin(), summary_.active_set_sizes.end()));
    c.set("contact/energy_time", summary_.time);
    c.set("contact/kinetic_energy", summary_.kinetic_energy);
    c.set("contact/strain_energy", summary_.strain_energy);
    c.set("contact/body_force_potential", summary_.body_force_potential);
    c.set("contact/friction_work", summary_.friction_work);
    c.set("contact/friction_work_total", friction_work_);
    c.set_text("contact/vtk_series", vtk_->entries());
  }

  template <int dim>
  void ContactProblem<dim>::load_state(const Checkpoint& c)
  {
    c.restore("contact/u", u_);
    c.restore("contact/lambda", lambda_);
    if (dynamics_)
      dynamics_->load(c, "contact/dynamics");
    c.restore("contact/force_old", contact_force_old_);
    time_        = c.number("contact/time");
    load_factor_ = load_factor_at(time_);
    set_prescribed_values(load_factor_, time_); // generalized-alpha's h_n needs the loads of t_n
    summary_.max_penetration = c.number("contact/max_penetration");
    const auto& sizes        = c.numbers("contact/active_set_sizes");
    summary_.active_set_sizes.assign(sizes.begin(), sizes.end());
    summary_.time           = c.numbers("contact/energy_time");
    summary_.kinetic_energy = c.numbers("contact/kinetic_energy");
    summary_.strain_energy  = c.numbers("contact/strain_energy");
    summary_.body_force_potential = c.numbers("contact/body_force_potential");
    summary_.friction_work  = c.numbers("contact/friction_work");
    friction_work_          = c.number("contact/friction_work_total");
    vtk_->restore(c.text("contact/vtk_series"));
    u_ghosted_      = u_;
    lambda_ghosted_ = lambda_;
    contact_->continue_active_set();
  }

  template <int dim>
  std::pair<double, int> ContactProblem<dim>::deepest_local_penetration() const
  {
    const auto&            state = contact_->state();
    std::pair<double, int> deepest(-std::numeric_limits<double>::infinity(), -1);
    for (unsigned int j = 0; j < state.weight.size(); ++j)
      if (contact_->owns_slave_node(j) && state.covered[j] && !state.released[j] &&
          -state.weighted_gap[j] / state.weight[j] > deepest.first)
        deepest = {-state.weighted_gap[j] / state.weight[j], static_cast<int>(j)};
    return deepest;
  }

  template <int dim>
  void ContactProblem<dim>::check_initial_overlap()
  {
    // One evaluation in the reference configuration (u = 0, lambda = 0): a slave node inside a
    // master body by more than round-off of the meshed geometry is a mesh that starts with
    // bodies overlapping, which the contact constraints would push apart in the first step
    // with an unphysical impulse. The active-set guess of the first real evaluation stays.
    ContactContribution unused;
    mark_step_start();
    contact_->evaluate(positions(contact_->slave_nodes()), positions(contact_->master_nodes()), slave_multipliers(),
                       [&](GlobalIndex dof) { return constraints_.is_constrained(dof); }, unused);
    contact_->restart_active_set();
    const double tolerance     = 1e-3 * contact_->minimal_slave_face_size();
    const auto [deepest, node] = deepest_local_penetration();
    std::ostringstream where;
    if (node >= 0 && deepest > tolerance)
      where << "mesh file '" << p_.mesh_file << "': bodies overlap at the start: the slave node at ("
            << contact_->slave_nodes()[node].reference << ") lies " << deepest
            << " inside the master surface (allowed: 1e-3 of the smallest slave face, " << tolerance
            << "); move the bodies apart";
    throw_if_any_rank_failed(where.str(), comm_);
  }

  template <int dim>
  void ContactProblem<dim>::check_converged_contact(int number, double time)
  {
    // The last evaluation is the converged state's: its largest penetration (of the nodes under
    // a contact constraint: a released prescribed node goes where its Dirichlet value puts it),
    // and self-contact, which the mortar pairs do not handle: stop rather than let it pass.
    const double penetration = Utilities::MPI::max(std::max(0.0, deepest_local_penetration().first), comm_);
    summary_.max_penetration = std::max(summary_.max_penetration, penetration);
    JsonLinesLog::Line line;
    line.add("converged_step", number).add("time", time).add("active", n_active_).add("max_penetration", penetration);
    if (contact_->frictional())
      line.add("slip", n_slip_).add("friction_work", friction_work_);
    log_.write(line);
    u_ghosted_             = u_;
    const std::string self = contact_->detect_self_contact(positions(contact_->slave_nodes()),
                                                           positions(contact_->master_nodes()),
                                                           positions(contact_->watch_nodes()));
    if (!self.empty())
      throw std::runtime_error("step " + std::to_string(number) + " (t = " + std::to_string(time) +
                               "): self-contact detected: " + self +
                               "; self-contact is not handled (a body is never paired with itself), the run "
                               "stops instead of letting the body penetrate itself");
  }

  template <int dim>
  void ContactProblem<dim>::final_state(ContactRunSummary& summary)
  {
    // The slave nodes' final state, each node from its owner, gathered on rank 0 (for the
    // summary and the CSV file only) in the order of their reference positions, which does not
    // depend on the partition.
    u_ghosted_        = u_;
    lambda_ghosted_   = lambda_;
    const auto& state = contact_->state();
    const auto  xs    = positions(contact_->slave_nodes());
    // Per node, 11 numbers: reference (3), position (3), pressure, weight, active, |lambda_tau|,
    // slip.
    constexpr std::size_t n_values = 11;
    std::vector<double>   mine;
    for (unsigned int j = 0; j < contact_->n_slave_nodes(); ++j)
      if (contact_->owns_slave_node(j))
        {
          std::array<double, n_values> row{};
          double                ln = 0;
          for (unsigned int d = 0; d < dim; ++d)
            {
              row[d]     = contact_->slave_nodes()[j].reference[d];
              row[3 + d] = xs[j][d];
              ln += contact_->normal(j)[d] * lambda_ghosted_[contact_->slave_nodes()[j].dofs[d]];
            }
          row[6] = ln;
          row[7] = state.weight[j];
          row[8]  = state.active[j] ? 1 : 0;
          row[9]  = state.tangential[j];
          row[10] = state.slip[j] ? 1 : 0;
          mine.insert(mine.end(), row.begin(), row.end());
        }
    auto all = Utilities::MPI::gather(comm_, mine, 0);
    if (rank_ == 0)
      {
        std::vector<std::array<double, n_values>> nodes;
        for (const auto& part : all)
          for (std::size_t i = 0; i + n_values <= part.size(); i += n_values)
            {
              std::array<double, n_values> row;
              std::copy(part.begin() + i, part.begin() + i + n_values, row.begin());
              nodes.push_back(row);
            }
        std::sort(nodes.begin(), nodes.end(), [](const auto& a, const auto& b) {
          return std::lexicographical_compare(a.begin(), a.begin() + 3, b.begin(), b.begin() + 3);
        });
        for (const auto& row : nodes)
          {
            summary.slave_positions.push_back({{row[3], row[4], row[5]}});
            summary.normal_pressure.push_back(row[6]);
            summary.weight.push_back(row[7]);
            summary.active.push_back(row[8] != 0);
            summary.tangential.push_back(row[9]);
            summary.slip.push_back(row[10] != 0);
          }
      }
    summary.max_displacement = u_.linfty_norm();
    summary.displacement_l2  = u_.l2_norm();
  }

  template <int dim>
  void ContactProblem<dim>::log_energies(int step, double time)
  {
    u_ghosted_           = u_;
    // total = kinetic + strain + the body force's potential; with the friction work added it is
    // what the bodies would hold without friction (constant up to the time discretization when
    // the loads do no other work).
    const double kinetic = dynamics_->kinetic_energy(),
                 strain  = strain_energy(dof_handler_, model_, u_ghosted_),
                 potential = body_force_potential(dof_handler_, model_, u_ghosted_);
    summary_.time.push_back(time);
    summary_.kinetic_energy.push_back(kinetic);
    summary_.strain_energy.push_back(strain);
    summary_.body_force_potential.push_back(potential);
    summary_.friction_work.push_back(friction_work_);
    JsonLinesLog::Line line;
    line.add("time_step", step)
        .add("time", time)
        .add("kinetic_energy", kinetic)
        .add("strain_energy", strain);
    if (model_.body_force.norm() > 0)
      line.add("body_force_potential", potential);
    line.add("total_energy", kinetic + strain + potential);
    if (contact_->frictional())
      line.add("friction_work", friction_work_);
    log_.write(line);
  }

  template <int dim>
  void ContactProblem<dim>::write_output(int step, double time, bool last)
  {
    if (!p_.vtk_due(step, last))
      return;
    TimerOutput::Scope scope(timer_, "output");
    u_ghosted_ = u_;
    // Nodal contact fields on the slave nodes, stored in vectors of the displacement layout:
    // the multiplier vector, and (pressure, active flag, normalized gap) as separate scalars.
    TrilinosWrappers::MPI::Vector fields(owned_, comm_);
    const auto&                   state = contact_->state();
    for (unsigned int j = 0; j < contact_->n_slave_nodes(); ++j)
      {
        const auto& node = contact_->slave_nodes()[j];
        if (!contact_->owns_slave_node(j))
          continue;
        fields[node.dofs[0]] = state.normal_pressure[j];
        fields[node.dofs[1]] = state.active[j] ? 1.0 : 0.0;
        if (dim == 3)
          fields[node.dofs[dim - 1]] = state.weight[j] > 0 ? state.weighted_gap[j] / state.weight[j] : 0.0;
      }
    fields.compress(VectorOperation::insert);
    TrilinosWrappers::MPI::Vector fields_g(owned_, relevant_, comm_);
    lambda_ghosted_ = lambda_;
    fields_g        = fields;

    DataOut<dim> out;
    out.attach_dof_handler(dof_handler_);
    SolidOutputFields<dim> solid;
    solid.attach(out, dof_handler_, model_, u_ghosted_);
    const std::vector<DataComponentInterpretation::DataComponentInterpretation> vector_field(
        dim, DataComponentInterpretation::component_is_part_of_vector);
    TrilinosWrappers::MPI::Vector velocity;
    if (dynamics_)
      {
        velocity.reinit(owned_, relevant_, comm_);
        velocity = dynamics_->velocity();
        out.add_data_vector(velocity, std::vector<std::string>(dim, "velocity"), DataOut<dim>::type_dof_data,
                            vector_field);
      }
    out.add_data_vector(lambda_ghosted_, std::vector<std::string>(dim, "contact_multiplier"),
                        DataOut<dim>::type_dof_data, vector_field);
    std::vector<std::string> names = {"contact_pressure", "active"};
    if (dim == 3)
      names.push_back("normal_gap");
    out.add_data_vector(fields_g, names, DataOut<dim>::type_dof_data,
                        std::vector<DataComponentInterpretation::DataComponentInterpretation>(
                            dim, DataComponentInterpretation::component_is_scalar));
    // Friction: |lambda_tau| and the slip flag (1: sliding, 0: sticking or not in contact), in 3D
    // also the slip of the step (the third component of the node's layout).
    TrilinosWrappers::MPI::Vector friction_g;
    if (contact_->frictional())
      {
        TrilinosWrappers::MPI::Vector friction(owned_, comm_);
        for (unsigned int j = 0; j < contact_->n_slave_nodes(); ++j)
          if (contact_->owns_slave_node(j))
            {
              friction[contact_->slave_nodes()[j].dofs[0]] = state.tangential[j];
              friction[contact_->slave_nodes()[j].dofs[1]] = state.slip[j] ? 1.0 : 0.0;
              if (dim == 3)
                friction[contact_->slave_nodes()[j].dofs[dim - 1]] = state.slip_distance[j];
            }
        friction.compress(VectorOperation::insert);
        friction_g.reinit(owned_, relevant_, comm_);
        friction_g = friction;
        std::vector<std::string> friction_names = {"tangential_traction", "slip"};
        if (dim == 3)
          friction_names.push_back("slip_distance");
        out.add_data_vector(friction_g, friction_names, DataOut<dim>::type_dof_data,
                            std::vector<DataComponentInterpretation::DataComponentInterpretation>(
                                dim, DataComponentInterpretation::component_is_scalar));
      }
    out.build_patches();
    vtk_->write(out, step, time);
  }

  template <int dim>
  void ContactProblem<dim>::setup_output()
  {
    summary_.slave_nodes = contact_->n_global_slave_nodes();
    summary_.max_slave_nodes_held =
        static_cast<long long>(Utilities::MPI::max(static_cast<double>(contact_->n_slave_nodes()), comm_));
    if (rank_ == 0)
      log_ = JsonLinesLog(p_.output_directory + "/run_log.jsonl");
    vtk_ = std::make_unique<VtkSeries>(p_.output_directory, "solution", comm_);
    pcout_ << "contact_blocks: " << dim << "D, " << tria_.n_global_active_cells() << " cells (at most "
           << Utilities::MPI::max(tria_.n_active_cells(), comm_) << " stored on a rank), "
           << dof_handler_.n_dofs() << " displacement DOFs, " << dim * contact_->n_global_slave_nodes()
           << " multipliers (" << (p_.dual ? "dual" : "standard") << "; at most "
           << summary_.max_slave_nodes_held << " of " << summary_.slave_nodes
           << " slave nodes held on a rank), " << Utilities::MPI::n_mpi_processes(comm_) << " ranks, preset "
           << p_.solver.preset;
    if (dynamics_)
      pcout_ << ", generalized-alpha (rho_inf " << p_.spectral_radius << ", dt " << p_.time_step << " s)";
    pcout_ << "\n";
    pcout_ << "contact: " << contact_->describe_pairs() << "\n";
  }

  // The class is instantiated once, in contact_problem.cc (an explicit instantiation of the
  // class may appear in one file only); here only the members this file defines.
#define PHYSICS_CONTACT_STATE_OUTPUT_MEMBERS(dim)                                                      \
  template void ContactProblem<dim>::describe(JsonLinesLog::Line&, std::ostream&) const;              \
  template std::string ContactProblem<dim>::checkpoint_kind() const;                                    \
  template void        ContactProblem<dim>::save_state(Checkpoint&) const;                              \
  template void        ContactProblem<dim>::load_state(const Checkpoint&);                              \
  template std::pair<double, int> ContactProblem<dim>::deepest_local_penetration() const;               \
  template void ContactProblem<dim>::check_initial_overlap();                                           \
  template void ContactProblem<dim>::check_converged_contact(int, double);                              \
  template void ContactProblem<dim>::final_state(ContactRunSummary&);                                   \
  template void ContactProblem<dim>::log_energies(int, double);                                         \
  template void ContactProblem<dim>::write_output(int, double, bool);                                   \
  template void ContactProblem<dim>::setup_output();
  PHYSICS_CONTACT_STATE_OUTPUT_MEMBERS(2)
  PHYSICS_CONTACT_STATE_OUTPUT_MEMBERS(3)
#undef PHYSICS_CONTACT_STATE_OUTPUT_MEMBERS
} // namespace physics::contact::internal
