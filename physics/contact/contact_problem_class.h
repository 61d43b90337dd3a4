// The contact problem class behind run_contact (contact_problem.h): its set-up, Newton steps
// and linearization in contact_problem.cc, its state checks, energies and output (log, VTK,
// summary) in contact_state_output.cc. Internal to those two files.
#pragma once

#include "common/distributed_mesh.h"
#include "common/newton_solver.h"
#include "common/row_exchange.h"
#include "common/run_output.h"
#include "common/solid_dynamics.h"
#include "common/solid_mechanics.h"
#include "common/step_driver.h"
#include "common/vtk_output.h"
#include "contact/contact_block_system.h"
#include "contact/contact_problem.h"

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/index_set.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/fully_distributed_tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/trilinos_vector.h>

#include <mpi.h>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <ostream>
#include <set>
#include <string>
#include <vector>

namespace physics::contact::internal
{
  template <int dim>
  class ContactProblem : public SteppedProblem
  {
  public:
    ContactProblem(const ContactParameters& p, MPI_Comm comm);
    ContactRunSummary run();

    // The nonlinear problem of one load/time step (common/newton_solver.h, step_driver.h).
    std::vector<std::string> field_names() const override { return ContactParameters::residual_fields(); }
    Linearization            linearize(int iteration) override;
    /// Semi-smooth Newton: an iterate counts only when its evaluation left the active set as it was.
    bool          may_converge() const override { return !active_set_changed_; }
    std::uint64_t state_signature() const override { return active_set_signature_; }
    void          update(const multigrid::MultiVector& dx) override;
    void          set_update_length(double step_length) override;
    void          describe(JsonLinesLog::Line& line, std::ostream& console) const override;
    std::string   console_header() const override
    {
      return p_.friction_coefficient > 0 ? "   active  changed     slip" : "   active  changed";
    }
    void          begin_step(double time, double step) override;
    void          reset_step() override;
    void          end_step(int number, double time) override;
    void          write_output(int number, double time, bool last) override;
    std::string   checkpoint_kind() const override;
    void          save_state(Checkpoint& checkpoint) const override;
    void          load_state(const Checkpoint& checkpoint) override;

  private:
    /// Output directory, mesh, DOFs, then the set-up steps below in order.
    void setup();
    /// Setup: the cells the mesh partition shares out evenly besides all cells (Balance contact
    /// surfaces; empty when it is off).
    CellMarker<dim> contact_surface_cells() const;
    /// Setup: every boundary id the parameters name must exist in the mesh (on some rank).
    void check_boundary_ids();
    /// Setup: the mortar contact surfaces, and the ghost DOFs they add to the relevant ones.
    void setup_contact();
    /// Setup: the material ids of the slave body (checked apart from the master body's).
    std::set<dealii::types::material_id> slave_body_materials() const;
    /// Setup: this rank's owned nodes with their body and surface membership.
    void collect_owned_nodes();
    /// Setup: the homogeneous constraints of the Newton update and the structural sparsity pattern.
    void setup_constraints();
    /// Setup: the material law of every cell and the displacement and multiplier vectors.
    void setup_model();
    /// Setup: summary sizes, the run log, the VTK series and the run's console description.
    void setup_output();
    /// The loads of load factor `load_factor` (quasi-static) or time `time` (dynamics): the
    /// prescribed displacements, the pressure, the body force.
    void set_prescribed_values(double load_factor, double time);
    /// The load factor of a (pseudo-)time: the load ramps linearly over all steps.
    double load_factor_at(double time) const
    {
      return dynamics_ ? time / (p_.load_steps * p_.time_step) : time;
    }
    /// Constraints of a load step's first Newton update: the homogeneous ones, with the jump
    /// of the prescribed values as inhomogeneity (so the increment is spread by the solve
    /// instead of being imposed on one layer of elements).
    dealii::AffineConstraints<double> increment_constraints() const;
    /// The constrained rows of the first update only say du_i = increment_i and their columns
    /// were eliminated by the lifting: they are taken out of the Krylov solve (zero right-hand
    /// side there) and set to their targets in update(). AMG hierarchies see the same operator,
    /// but no longer a right-hand side concentrated on decoupled rows.
    void                                 lift_prescribed_rows();
    std::vector<std::array<double, dim>> positions(const std::vector<SurfaceNode<dim>>& nodes) const;
    /// The multipliers of this rank's slave nodes (dim each) from the ghosted multiplier vector.
    std::vector<double> slave_multipliers();
    /// Friction: the current positions are the start of a step, from which the slip is measured.
    void mark_step_start();
    /// Active-set bookkeeping of the last evaluation against the previous one of this step.
    void count_active_set();
    void final_state(ContactRunSummary& summary);
    /// After a converged step: the largest penetration (log, summary) and the self-contact check.
    void check_converged_contact(int number, double time);
    /// Setup: a mesh whose bodies overlap in the reference configuration is bad input.
    void check_initial_overlap();
    /// The largest -g~_j / w_j of the last evaluation over this rank's owned covered slave nodes
    /// and that node (-inf and -1 if it owns none).
    std::pair<double, int> deepest_local_penetration() const;

    // Dynamics (generalized-alpha; see common/solid_dynamics.h).
    /// Mass matrix, initial velocity of the slave body, initial acceleration.
    void setup_dynamics();
    /// The energies of the current state (a log line and the summary).
    void log_energies(int step, double time);
    /// Contact forces at the generalized midpoint: (1 - af) (this step) + af (previous step).
    void weight_contact_forces(ContactContribution& contribution);

    const ContactParameters&   p_;
    MPI_Comm                   comm_;
    const unsigned int         rank_;
    dealii::ConditionalOStream pcout_;
    dealii::TimerOutput        timer_;

    dealii::parallel::fullydistributed::Triangulation<dim> tria_;
    dealii::FESystem<dim>                                  fe_;
    dealii::DoFHandler<dim>                                dof_handler_;
    dealii::IndexSet                                       owned_, relevant_, ghosts_;
    std::vector<dealii::IndexSet>                          owned_per_rank_;
    dealii::AffineConstraints<double>                      constraints_;
    dealii::DynamicSparsityPattern                         structural_pattern_;
    SolidModel<dim>                                        model_;
    std::map<dealii::types::global_dof_index, double>      prescribed_; ///< loaded-face values this step
    std::unique_ptr<MortarContact<dim>>                    contact_;
    std::vector<OwnedNode<dim>>                            owned_nodes_;

    std::unique_ptr<SolidDynamics<dim>> dynamics_; ///< null: quasi-static
    /// This rank's share of the contact force D^T lambda - M^T lambda at t_n and at the latest
    /// evaluation.
    std::map<GlobalIndex, double> contact_force_old_, contact_force_new_;

    dealii::TrilinosWrappers::MPI::Vector u_, u_ghosted_;
    /// Multipliers in the displacement layout: lambda_j at slave node j's DOFs (owned rows; the
    /// ghosted copy reaches the slave nodes of the ghost faces).
    dealii::TrilinosWrappers::MPI::Vector lambda_, lambda_ghosted_;
    JsonLinesLog                          log_;
    std::unique_ptr<VtkSeries>            vtk_;
    ContactRunSummary                     summary_;

    // The step in progress
    double                                time_ = 0, load_factor_ = 0;
    dealii::TrilinosWrappers::MPI::Vector u_begin_; ///< state at the step's start (reset_step)
    dealii::TrilinosWrappers::MPI::Vector lambda_begin_;
    std::vector<bool>                     previous_active_; ///< of the previous evaluation in this step
    /// No evaluation yet in this step (a rank may hold no slave node: not `previous_active_`'s size).
    bool                first_in_step_ = true;
    std::vector<bool>   previous_slip_;   ///< friction: of the previous evaluation in this step
    int                 n_active_ = 0, n_changed_ = 0, n_slip_ = 0;
    double              friction_work_ = 0; ///< energy dissipated by friction up to the last step
    bool                active_set_changed_   = true;
    std::uint64_t       active_set_signature_ = 0; ///< of the last evaluation (see count_active_set)
    ContactLinearSystem linear_;                   ///< the last linearization
    std::map<std::size_t, double> lifted_;         ///< local row -> prescribed target (first update)
    /// The last update's Newton direction without the prescribed rows, and its applied length
    /// (line search).
    dealii::TrilinosWrappers::MPI::Vector du_direction_;
    dealii::TrilinosWrappers::MPI::Vector dlambda_direction_;
    double                                update_length_ = 1;
  };
} // namespace physics::contact::internal
