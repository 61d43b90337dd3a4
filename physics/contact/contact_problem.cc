#include "contact/contact_problem.h"

#include "contact/contact_problem_class.h"

#include "common/distributed_mesh.h"
#include "common/newton_solver.h"
#include "common/row_exchange.h"
#include "common/run_directory.h"
#include "common/run_output.h"
#include "common/solid_dynamics.h"
#include "common/solid_mechanics.h"
#include "common/step_driver.h"
#include "common/vtk_output.h"
#include "contact/contact_block_system.h"

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/fully_distributed_tria.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <set>
#include <sstream>
#include <utility>

namespace physics::contact
{
  using namespace dealii;

  namespace
  {
    /// splitmix64's finalizer: spreads the bits of a DOF number over the word (active-set signature).
    std::uint64_t mix_bits(std::uint64_t z)
    {
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
      return z ^ (z >> 31);
    }
  } // namespace

  namespace internal
  {
    template <int dim>
    ContactProblem<dim>::ContactProblem(const ContactParameters& p, MPI_Comm comm)
        : p_(p)
        , comm_(comm)
        , rank_(Utilities::MPI::this_mpi_process(comm))
        , pcout_(std::cout, rank_ == 0)
        , timer_(pcout_, TimerOutput::never, TimerOutput::wall_times)
        , tria_(comm)
        , fe_(FE_Q<dim>(1), dim)
        , dof_handler_(tria_)
    {
    }

    template <int dim>
    void ContactProblem<dim>::setup()
    {
      TimerOutput::Scope scope(timer_, "setup");
      prepare_output_directory(p_.output_directory, comm_);
      read_distributed_mesh(p_.mesh_file, p_.gmsh_source(), p_.global_refinements, p_.output_directory, tria_,
                            contact_surface_cells());
      check_boundary_ids();

      dof_handler_.distribute_dofs(fe_);
      owned_ = dof_handler_.locally_owned_dofs();
      DoFTools::extract_locally_relevant_dofs(dof_handler_, relevant_);
      owned_per_rank_ = Utilities::MPI::all_gather(comm_, owned_);

      setup_contact();
      collect_owned_nodes();
      setup_constraints();
      setup_model();
      check_initial_overlap();
      if (p_.dynamic())
        setup_dynamics();
      setup_output();
    }

    template <int dim>
    CellMarker<dim> ContactProblem<dim>::contact_surface_cells() const
    {
      if (!p_.balance_contact_surface)
        return {};
      // The faces whose owners evaluate mortar integrals: the slave surface of two bodies; with
      // several bodies every contact surface (which bodies are slaves is decided later, from
      // the pairs, and every body is a slave in some pair with 'auto').
      std::set<types::boundary_id> ids;
      if (p_.multi_body())
        ids.insert(p_.surface_ids.begin(), p_.surface_ids.end());
      else
        ids.insert(static_cast<types::boundary_id>(p_.slave_id));
      return [ids](const typename Triangulation<dim>::active_cell_iterator& cell) {
        for (const unsigned int f : cell->face_indices())
          if (cell->face(f)->at_boundary() && ids.count(cell->face(f)->boundary_id()))
            return true;
        return false;
      };
    }

    template <int dim>
    void ContactProblem<dim>::check_boundary_ids()
    {
      // Every id the parameters name must exist in the mesh (on some rank).
      std::set<types::boundary_id> ids;
      for (const auto& cell : tria_.active_cell_iterators())
        if (cell->is_locally_owned())
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary())
              ids.insert(cell->face(f)->boundary_id());
      ids = Utilities::MPI::compute_set_union(ids, comm_);
      auto require = [&](int id, const std::string& parameter) {
        if (!ids.count(static_cast<types::boundary_id>(id)))
          throw std::invalid_argument(p_.mesh_file + ": no boundary faces with id " + std::to_string(id) +
                                      " (parameter '" + parameter + "')");
      };
      if (p_.multi_body())
        for (const int id : p_.surface_ids)
          require(id, "Contact surface ids");
      else
        {
          require(p_.slave_id, "Slave boundary id");
          require(p_.master_id, "Master boundary id");
        }
      for (const int id : p_.watch_ids)
        require(id, "Self-contact check ids");
      if (p_.clamped_id >= 0)
        require(p_.clamped_id, "Clamped boundary id");
      if (p_.load_type != "none")
        require(p_.loaded_id, "Loaded boundary id");
      for (std::size_t i = 0; i < p_.symmetry.size(); i += 2)
        require(p_.symmetry[i], "Symmetry");
    }

    template <int dim>
    void ContactProblem<dim>::setup_contact()
    {
      ContactSettings settings;
      settings.slave_boundary       = p_.slave_id;
      settings.master_boundary      = p_.master_id;
      settings.dual                 = p_.dual;
      settings.search_radius_factor = p_.search_radius_factor;
      settings.friction_coefficient = p_.friction_coefficient;
      settings.prescribed_nodes_contact = p_.prescribed_slave_contact;
      settings.surface_boundaries.assign(p_.surface_ids.begin(), p_.surface_ids.end());
      settings.watch_boundaries.assign(p_.watch_ids.begin(), p_.watch_ids.end());
      for (const auto& [slave, master] : p_.pairs)
        settings.pairs.emplace_back(slave, master);
      contact_ = std::make_unique<MortarContact<dim>>(dof_handler_, settings);
      const double stiffness_per_length = p_.youngs_modulus / contact_->minimal_slave_face_size();
      contact_->set_complementarity_parameters(p_.complementarity_factor * stiffness_per_length,
                                               p_.tangential_factor * stiffness_per_length);

      ghosts_ = relevant_;
      {
        const auto surface = contact_->surface_dofs();
        IndexSet   s(dof_handler_.n_dofs());
        s.add_indices(surface.begin(), surface.end());
        ghosts_.add_indices(s);
      }
    }

    template <int dim>
    std::set<types::material_id> ContactProblem<dim>::slave_body_materials() const
    {
      // Two-body mode: the material ids next to the slave faces are the slave body (label 1), the
      // rest the master body (label 0). Multi-body mode: every material id is a body (its label).
      std::set<types::material_id> slave_materials, master_materials;
      for (const auto& cell : tria_.active_cell_iterators())
        if (cell->is_locally_owned())
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary())
              {
                if (cell->face(f)->boundary_id() == static_cast<types::boundary_id>(p_.slave_id))
                  slave_materials.insert(cell->material_id());
                if (cell->face(f)->boundary_id() == static_cast<types::boundary_id>(p_.master_id))
                  master_materials.insert(cell->material_id());
              }
      slave_materials  = Utilities::MPI::compute_set_union(slave_materials, comm_);
      master_materials = Utilities::MPI::compute_set_union(master_materials, comm_);
      if (p_.multi_body())
        slave_materials = contact_->slave_bodies();
      for (auto m : slave_materials)
        if (!p_.multi_body() && master_materials.count(m))
          throw std::invalid_argument(p_.mesh_file + ": slave and master faces lie on the same body (material id " +
                                      std::to_string(m) + "); expected two bodies with their own physical volumes");
      return slave_materials;
    }

    template <int dim>
    void ContactProblem<dim>::collect_owned_nodes()
    {
      const std::set<types::material_id> slave_materials = slave_body_materials();

      // Locally owned nodes with body and surface membership.
      std::map<GlobalIndex, int> slave_of_dof;
      std::set<GlobalIndex>      master_dofs;
      for (unsigned int j = 0; j < contact_->n_slave_nodes(); ++j)
        if (contact_->owns_slave_node(j))
          slave_of_dof[contact_->slave_nodes()[j].dofs[0]] = j;
      for (const auto& node : contact_->master_nodes())
        master_dofs.insert(node.dofs[0]);
      std::map<GlobalIndex, OwnedNode<dim>> nodes;
      for (const auto& cell : dof_handler_.active_cell_iterators())
        for (const unsigned int v : cell->vertex_indices())
          {
            if (cell->is_artificial())
              break;
            const GlobalIndex dof0 = cell->vertex_dof_index(v, 0);
            if (!owned_.is_element(dof0))
              continue;
            const bool slave_body = slave_materials.count(cell->material_id()) > 0;
            const int  body       = p_.multi_body() ? static_cast<int>(cell->material_id()) : slave_body;
            auto       it         = nodes.find(dof0);
            if (it != nodes.end())
              {
                if (it->second.body != body)
                {
                  std::ostringstream where;
                  where << cell->vertex(v);
                  throw std::invalid_argument(p_.mesh_file + ": two bodies share the node at (" + where.str() +
                                              "); mesh them separately (Geometry.AutoCoherence = 0)");
                }
                continue;
              }
            OwnedNode<dim> node;
            for (unsigned int d = 0; d < dim; ++d)
              {
                node.dofs[d]      = cell->vertex_dof_index(v, d);
                node.reference[d] = cell->vertex(v)[d];
              }
            node.slave_body     = slave_body;
            node.body           = body;
            node.master_surface = master_dofs.count(dof0) > 0;
            if (const auto s = slave_of_dof.find(dof0); s != slave_of_dof.end())
              node.slave_index = s->second;
            nodes.emplace(dof0, node);
          }
      for (auto& [dof, node] : nodes)
        owned_nodes_.push_back(node);
    }

    template <int dim>
    void ContactProblem<dim>::setup_constraints()
    {
      // Homogeneous constraints of the Newton update: clamped, loaded (displacement control),
      // symmetry planes (one component).
      // Known for the surface DOFs too: contact entries in constrained rows and columns are
      // dropped on every rank alike.
      constraints_.clear();
      constraints_.reinit(ghosts_);
      const Functions::ZeroFunction<dim> zero(dim);
      if (p_.clamped_id >= 0)
        add_boundary_constraints(dof_handler_, p_.clamped_id, zero, constraints_);
      if (p_.load_type == "displacement")
        add_boundary_constraints(dof_handler_, p_.loaded_id, zero, constraints_);
      for (std::size_t i = 0; i < p_.symmetry.size(); i += 2)
        add_boundary_constraints(dof_handler_, p_.symmetry[i], zero, constraints_,
                                 fe_.component_mask(FEValuesExtractors::Scalar(p_.symmetry[i + 1])));
      close_distributed_constraints(dof_handler_, ghosts_, constraints_);

      structural_pattern_.reinit(relevant_.size(), relevant_.size(), relevant_);
      DoFTools::make_sparsity_pattern(dof_handler_, structural_pattern_, constraints_, false);
      SparsityTools::distribute_sparsity_pattern(structural_pattern_, owned_, comm_, relevant_);
    }

    template <int dim>
    void ContactProblem<dim>::setup_model()
    {
      const auto lame    = LameParameters::from_young_poisson(p_.youngs_modulus, p_.poisson_ratio);
      std::shared_ptr<const HyperelasticMaterial<dim>> law = make_material<dim>(p_.law, lame);
      for (const auto& cell : tria_.active_cell_iterators())
        {
          model_.materials[cell->material_id()] = law;
          model_.densities[cell->material_id()] = p_.density; // inertia and the body force
        }
      u_.reinit(owned_, comm_);
      u_ghosted_.reinit(owned_, ghosts_, comm_);
      lambda_.reinit(owned_, comm_);
      lambda_ghosted_.reinit(owned_, relevant_, comm_);
    }

    template <int dim>
    void ContactProblem<dim>::setup_dynamics()
    {
      dynamics_ = std::make_unique<SolidDynamics<dim>>(p_.spectral_radius, p_.time_step, dof_handler_, model_, owned_,
                                                       relevant_, comm_);
      auto& v = dynamics_->velocity();
      if (!p_.initial_velocity.empty())
        for (const auto& node : owned_nodes_)
          if (node.slave_body)
            for (unsigned int d = 0; d < dim; ++d)
              if (!constraints_.is_constrained(node.dofs[d]))
                v[node.dofs[d]] = p_.initial_velocity[d];
      v.compress(VectorOperation::insert);
      set_prescribed_values(0.0, 0.0);
      dynamics_->initial_acceleration(u_, constraints_); // contact forces are zero at t0 (lambda = 0)
    }

    template <int dim>
    void ContactProblem<dim>::weight_contact_forces(ContactContribution& contribution)
    {
      contact_force_new_ = contribution.residual;
      const auto&  scheme = dynamics_->scheme();
      const double w      = scheme.force_weight();
      for (auto& [row, value] : contribution.residual)
        value *= w;
      for (const auto& [row, value] : contact_force_old_)
        contribution.residual[row] += scheme.alpha_f() * value;
      // Displacement rows' derivatives (w.r.t. u and lambda) carry the same weight; the
      // constraint rows (multiplier indices) are enforced at t_{n+1} and keep theirs.
      for (auto& [row, entries] : contribution.matrix)
        if (row < dof_handler_.n_dofs())
          for (auto& [column, value] : entries)
            value *= w;
    }

    template <int dim>
    void ContactProblem<dim>::set_prescribed_values(double load_factor, double time)
    {
      if (!p_.gravity.empty())
        {
          const double factor = !dynamics_                   ? load_factor
                                : p_.gravity_ramp_time > 0.0 ? std::min(1.0, time / p_.gravity_ramp_time)
                                                             : 1.0;
          for (unsigned int d = 0; d < dim; ++d)
            model_.body_force[d] = factor * p_.gravity[d];
        }
      if (p_.load_type == "displacement")
        {
          Vector<double> value(dim);
          for (unsigned int d = 0; d < dim; ++d)
            value[d] = load_factor * p_.displacement[d];
          prescribed_.clear();
          VectorTools::interpolate_boundary_values(dof_handler_, p_.loaded_id,
                                                   Functions::ConstantFunction<dim>(value), prescribed_);
        }
      else if (p_.load_type == "pressure")
        {
          model_.tractions.clear();
          // A dead nominal pressure: traction -p N0 with N0 the reference outward normal. The
          // loaded face must be flat: its normal is taken from the first face found.
          for (const auto& cell : tria_.active_cell_iterators())
            for (const unsigned int f : cell->face_indices())
              if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == static_cast<types::boundary_id>(p_.loaded_id) &&
                  model_.tractions.empty())
                {
                  Tensor<1, dim> n = cell->face(f)->center() - cell->center();
                  // project onto the face normal: for axis-aligned boxes the dominant axis
                  unsigned int axis = 0;
                  for (unsigned int d = 1; d < dim; ++d)
                    if (std::abs(n[d]) > std::abs(n[axis]))
                      axis = d;
                  Tensor<1, dim> t;
                  t[axis] = -(n[axis] > 0 ? 1.0 : -1.0) * load_factor * p_.pressure;
                  model_.tractions[p_.loaded_id] = t;
                }
        }
    }

    template <int dim>
    AffineConstraints<double> ContactProblem<dim>::increment_constraints() const
    {
      // Newton solves K du = -r; deal.II's lifting puts (diagonal x inhomogeneity) into the
      // residual of a constrained row, hence the minus sign.
      AffineConstraints<double> c;
      c.reinit(ghosts_);
      for (const auto& line : constraints_.get_lines())
        {
          const auto   it     = prescribed_.find(line.index);
          const double target = it == prescribed_.end() ? 0.0 : it->second;
          c.add_line(line.index);
          c.set_inhomogeneity(line.index, -(target - u_ghosted_[line.index]));
        }
      c.close();
      return c;
    }

    template <int dim>
    std::vector<std::array<double, dim>> ContactProblem<dim>::positions(const std::vector<SurfaceNode<dim>>& nodes) const
    {
      std::vector<std::array<double, dim>> x(nodes.size());
      for (std::size_t i = 0; i < nodes.size(); ++i)
        for (unsigned int d = 0; d < dim; ++d)
          x[i][d] = nodes[i].reference[d] + u_ghosted_[nodes[i].dofs[d]];
      return x;
    }

    template <int dim>
    std::vector<double> ContactProblem<dim>::slave_multipliers()
    {
      lambda_ghosted_ = lambda_;
      std::vector<double> lambda;
      for (const auto& node : contact_->slave_nodes())
        for (unsigned int d = 0; d < dim; ++d)
          lambda.push_back(lambda_ghosted_[node.dofs[d]]);
      return lambda;
    }

    template <int dim>
    void ContactProblem<dim>::mark_step_start()
    {
      if (!contact_->frictional())
        return;
      u_ghosted_ = u_;
      contact_->set_step_start(positions(contact_->slave_nodes()), positions(contact_->master_nodes()));
    }

    template <int dim>
    void ContactProblem<dim>::begin_step(double time, double step)
    {
      time_        = time;
      load_factor_ = load_factor_at(time);
      u_begin_     = u_;
      lambda_begin_ = lambda_;
      mark_step_start();
      previous_active_.clear();
      previous_slip_.clear();
      first_in_step_ = true;
      if (dynamics_)
        {
          dynamics_->set_time_step(step);
          dynamics_->begin_step(u_, constraints_); // before the loads move on to t_{n+1}
        }
      set_prescribed_values(load_factor_, time);
    }

    template <int dim>
    void ContactProblem<dim>::reset_step()
    {
      u_      = u_begin_;
      lambda_ = lambda_begin_;
    }

    template <int dim>
    void ContactProblem<dim>::count_active_set()
    {
      // Each node counted by its owner.
      const auto& state = contact_->state();
      n_active_ = n_changed_ = 0;
      // The set's signature: a sum of hashes of the active nodes' first DOF (order- and
      // partition-independent; unsigned sums wrap), plus one so that "no node active" is a state
      // too (0 means "no state" to the Newton solver).
      // With friction the stick/slip split is part of the state: a node that changes from stick
      // to slip counts as a change, and slip nodes enter the signature with their second DOF.
      const bool    friction  = contact_->frictional();
      std::uint64_t signature = 0;
      n_slip_                 = 0;
      for (unsigned int j = 0; j < state.active.size(); ++j)
        if (contact_->owns_slave_node(j))
          {
            n_active_ += state.active[j];
            n_changed_ += !first_in_step_ && previous_active_[j] != state.active[j];
            if (state.active[j])
              signature += mix_bits(contact_->slave_nodes()[j].dofs[0]);
            if (!friction)
              continue;
            n_slip_ += state.slip[j];
            const bool was_active = !first_in_step_ && previous_active_[j];
            n_changed_ += was_active && state.active[j] && previous_slip_[j] != state.slip[j];
            if (state.slip[j])
              signature += mix_bits(contact_->slave_nodes()[j].dofs[1]);
          }
      n_active_           = Utilities::MPI::sum(n_active_, comm_);
      n_changed_          = Utilities::MPI::sum(n_changed_, comm_);
      n_slip_             = Utilities::MPI::sum(n_slip_, comm_);
      previous_slip_      = state.slip;
      MPI_Allreduce(MPI_IN_PLACE, &signature, 1, MPI_UINT64_T, MPI_SUM, comm_);
      active_set_signature_ = signature + 1;
      active_set_changed_ = first_in_step_ || n_changed_ > 0;
      previous_active_    = state.active;
      first_in_step_      = false;
      summary_.active_set_sizes.push_back(n_active_);
    }

    template <int dim>
    Linearization ContactProblem<dim>::linearize(int iteration)
    {
      u_ghosted_ = u_;
      ContactContribution contribution;
      {
        TimerOutput::Scope scope(timer_, "contact evaluation");
        contact_->evaluate(positions(contact_->slave_nodes()), positions(contact_->master_nodes()), slave_multipliers(),
                           [&](GlobalIndex dof) { return constraints_.is_constrained(dof); }, contribution);
      }
      if (dynamics_)
        weight_contact_forces(contribution);
      count_active_set();
      // The last Newton matrix is freed before the next is built (its row numbering, which
      // update() needed, is replaced below as well).
      linear_.system = multigrid::BlockSystem();

      TrilinosWrappers::SparseMatrix K;
      K.reinit(owned_, owned_, structural_pattern_, comm_);
      TrilinosWrappers::MPI::Vector  residual(owned_, comm_);
      assemble_solid(dof_handler_, model_, u_ghosted_, iteration == 0 ? increment_constraints() : constraints_,
                     residual, &K, dynamics_ ? dynamics_->weights() : ResidualWeights{});
      if (dynamics_)
        residual += dynamics_->history();
      const auto owner = [&](GlobalIndex row) -> unsigned int {
        // A multiplier row n_dofs + dof belongs to the owner of its node's DOF.
        return owning_rank(owned_per_rank_, row >= dof_handler_.n_dofs() ? row - dof_handler_.n_dofs() : row);
      };
      const auto rows = send_rows_to_owners(contribution.matrix, owner, comm_);
      std::map<GlobalIndex, double> pieces = contribution.residual;
      for (const auto& [row, value] : contribution.constraint_residual)
        pieces[row] += value;
      pieces  = send_entries_to_owners(pieces, owner, comm_);
      // The near-nullspace's rotations turn about the current positions of the nodes.
      for (auto& node : owned_nodes_)
        for (unsigned int d = 0; d < dim; ++d)
          node.position[d] = node.reference[d] + u_ghosted_[node.dofs[d]];
      linear_ = build_contact_system<dim>(comm_, owned_nodes_, *contact_, owned_, ghosts_, K, residual, rows, pieces);

      Linearization result;
      result.system         = &linear_.system;
      result.residual_norms = linear_.system.block_norms(*linear_.system.rhs());
      result.residual_scales = {0.0, lambda_.l2_norm()};
      lifted_.clear();
      if (iteration == 0)
        lift_prescribed_rows();
      return result;
    }

    template <int dim>
    void ContactProblem<dim>::lift_prescribed_rows()
    {
      auto b = linear_.system.rhs()->getDataNonConst(0);
      for (std::size_t i = 0; i < linear_.assembly_index.size(); ++i)
        {
          const GlobalIndex a = linear_.assembly_index[i];
          if (a < dof_handler_.n_dofs() && constraints_.is_constrained(a))
            {
              const auto t = prescribed_.find(a);
              lifted_[i]   = t == prescribed_.end() ? 0.0 : t->second;
              b[i]         = 0.0;
            }
        }
    }

    template <int dim>
    void ContactProblem<dim>::update(const multigrid::MultiVector& dx)
    {
      // From the system's rows (assembly numbering) to u and lambda. Lifted rows go to their
      // targets; they are not part of the direction a line search scales.
      // Multiplier rows are owned with their slave node's DOFs: every entry lands in owned rows.
      const auto          data = dx.getData(0);
      dlambda_direction_.reinit(owned_, comm_);
      du_direction_.reinit(owned_, comm_);
      TrilinosWrappers::MPI::Vector lifted(owned_, comm_);
      for (std::size_t i = 0; i < linear_.assembly_index.size(); ++i)
        {
          const GlobalIndex a = linear_.assembly_index[i];
          if (a >= dof_handler_.n_dofs())
            dlambda_direction_[a - dof_handler_.n_dofs()] = data[i];
          else if (const auto target = lifted_.find(i); target != lifted_.end())
            lifted[a] = target->second - u_[a];
          else
            du_direction_[a] = data[i];
        }
      du_direction_.compress(VectorOperation::insert);
      dlambda_direction_.compress(VectorOperation::insert);
      lifted.compress(VectorOperation::insert);
      u_ += lifted;
      update_length_ = 0;
      set_update_length(1.0);
    }

    template <int dim>
    void ContactProblem<dim>::set_update_length(double step_length)
    {
      const double change = step_length - update_length_;
      u_.add(change, du_direction_);
      lambda_.add(change, dlambda_direction_);
      update_length_ = step_length;
    }

    template <int dim>
    void ContactProblem<dim>::end_step(int number, double time)
    {
      // The last evaluation is the converged state's: its nodes' lambda_tau . u is what friction
      // dissipated in the step (each node counted by its owner).
      double work = 0;
      for (unsigned int j = 0; j < contact_->n_slave_nodes(); ++j)
        if (contact_->owns_slave_node(j) && contact_->state().active[j])
          work += contact_->state().dissipation[j];
      friction_work_ += Utilities::MPI::sum(work, comm_);
      check_converged_contact(number, time);
      if (!dynamics_)
        return;
      dynamics_->end_step(u_);
      contact_force_old_ = contact_force_new_; // the converged state's (last evaluation)
      log_energies(number, time);
    }

    template <int dim>
    ContactRunSummary ContactProblem<dim>::run()
    {
      setup();
      if (dynamics_)
        log_energies(0, 0.0); // the initial state's

      NewtonSettings newton_settings  = p_.solver.newton_settings(field_names());
      p_.set_exports(newton_settings);
      NewtonSolver newton(newton_settings, p_.solver.load_preset(), p_.solver.solve_options(), log_, pcout_, timer_,
                          comm_);
      const StepSettings steps = dynamics_ ? p_.solver.step_settings(p_.load_steps * p_.time_step, p_.time_step, p_.output_directory)
                                           : p_.solver.step_settings(1.0, 1.0 / p_.load_steps, p_.output_directory);
      const StepsResult result = run_steps(*this, steps, newton, log_, pcout_);

      summary_.record(result);
      if (!result.converged)
        pcout_ << "Newton did not converge in load step " << result.steps + 1 << ": " << result.failure << "\n";
      final_state(summary_);
      log_timer_summary(timer_, log_, std::cout, rank_ == 0, comm_);
      return summary_;
    }

    template class ContactProblem<2>;
    template class ContactProblem<3>;
  } // namespace internal

  ContactRunSummary run_contact(const ContactParameters& parameters, MPI_Comm comm)
  {
    if (parameters.dimension == 2)
      return internal::ContactProblem<2>(parameters, comm).run();
    return internal::ContactProblem<3>(parameters, comm).run();
  }
} // namespace physics::contact
