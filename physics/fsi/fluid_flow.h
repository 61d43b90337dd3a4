// The fluid field of the FSI class on its own: the ALE Navier-Stokes equations of ale_fluid.h
// on a mesh whose motion is prescribed (or at rest, or pseudo-elastic from prescribed boundary
// motion), stepped in time by the common step driver
// and solved by the common Newton method with the full AD Jacobian. The fluid unknowns (u, p)
// are numbered node by node (dim + 1 DOFs per node), so the Newton system is handed over as a
// one-block BlockSystem ("fluid", velocity/pressure constants as near-nullspace).
//
// It serves the fluid's verification (Poiseuille, Kovasznay, geometric conservation:
// tests/test_fsi_fluid.cc); the coupled problem (condensed_fsi.h) calls the same assembler.
#pragma once

#include "common/step_driver.h"
#include "fsi/ale_fluid.h"
#include "fsi/ale_mesh_motion.h"

#include "block_system.h"

#include <deal.II/base/function.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <map>
#include <memory>
#include <optional>

namespace physics::fsi
{
  template <int dim>
  struct FluidFlowSetup
  {
    FluidModel<dim> model;
    /// Dirichlet velocity per boundary id: functions of (X, t) with dim + 1 components (the
    /// velocity's; the last is not read).
    std::map<dealii::types::boundary_id, std::shared_ptr<dealii::Function<dim>>> velocity;
    /// The pressure at one mesh vertex (needed when the velocity is prescribed on the whole
    /// boundary): the vertex and a function whose last component gives the value.
    std::optional<std::pair<dealii::Point<dim>, std::shared_ptr<dealii::Function<dim>>>> pressure_point;
    /// Prescribed grid displacement d^G(X, t) (dim components); null: the mesh is at rest.
    std::shared_ptr<dealii::Function<dim>> mesh_motion;
    /// If set, mesh_motion is prescribed on the boundary only and the interior follows the
    /// pseudo-elastic mesh motion (ale_mesh_motion.h).
    std::optional<MeshMotionSettings> pseudo_elastic;
  };

  /// Discretization errors against an exact solution (dim + 1 components: u, p).
  struct FlowErrors
  {
    double velocity_l2 = 0, velocity_h1 = 0; ///< ||u - u_h||, |u - u_h|_1
    double pressure_l2 = 0;                  ///< of the mean-free pressures
  };

  template <int dim>
  class FluidFlow : public SteppedProblem
  {
  public:
    /// `tria` is the reference mesh (parallel::distributed or serial); it must outlive this.
    FluidFlow(const dealii::Triangulation<dim>& tria, FluidFlowSetup<dim> setup, MPI_Comm comm);

    // SteppedProblem (common/step_driver.h)
    std::vector<std::string> field_names() const override { return {"momentum", "continuity"}; }
    Linearization            linearize(int iteration) override;
    void                     update(const multigrid::MultiVector& dx) override;
    void                     set_update_length(double step_length) override;
    void                     begin_step(double time, double step) override;
    void                     reset_step() override;
    void                     end_step(int number, double time) override;
    void                     write_output(int, double, bool) override {}

    /// The iterate (u, p) with its ghosts (after update / end_step).
    const dealii::TrilinosWrappers::MPI::Vector& solution() const { return ghosted_; }
    const dealii::TrilinosWrappers::MPI::Vector& owned_solution() const { return solution_; }
    const dealii::DoFHandler<dim>&               dof_handler() const { return dofs_; }
    /// The grid displacement d^G of the current step (ghosted) on its DoFHandler.
    const dealii::TrilinosWrappers::MPI::Vector& mesh_displacement() const { return mesh_; }
    const dealii::DoFHandler<dim>&               mesh_dof_handler() const { return mesh_dofs_; }
    /// Sets the iterate and the history of the time derivative to `initial` (at rest in time:
    /// zero rates), the mesh and its history to the motion at t = 0.
    void set_initial_state(const dealii::Function<dim>& initial);
    /// ||R|| of the current iterate (no Jacobian): for consistency checks.
    double residual_norm();
    /// Errors against `exact` (dim + 1 components) on the reference mesh (a mesh at rest).
    FlowErrors              errors(dealii::Function<dim>& exact) const;
    const dealii::IndexSet& owned_dofs() const { return owned_; }
    /// The Newton increment's (homogeneous) Dirichlet constraints.
    const dealii::AffineConstraints<double>& constraints() const { return constraints_; }

  private:
    void setup_dofs();
    /// Dirichlet values of time `time` into `values` (inhomogeneous) and the iterate.
    void                   apply_dirichlet(double time);
    void                   assemble(bool with_jacobian);
    /// The model of the current step (BDF2's first step is BDF1).
    FluidModel<dim> step_model() const;
    multigrid::BlockSystem block_system() const;
    void                   update_ghosts();
    /// d^G at `time`: the prescribed motion, or its boundary values extended pseudo-elastically.
    void move_mesh(double time);

    FluidFlowSetup<dim>                    s_;
    MPI_Comm                               comm_;
    dealii::FESystem<dim>                  fe_, mesh_fe_;
    dealii::DoFHandler<dim>                dofs_, mesh_dofs_;
    dealii::IndexSet                       owned_, relevant_, mesh_owned_, mesh_relevant_;
    dealii::AffineConstraints<double>      constraints_;   ///< homogeneous: the Newton increment
    dealii::IndexSet                       pressure_dofs_; ///< owned pressure DOFs (the continuity field)
    dealii::TrilinosWrappers::SparseMatrix jacobian_;
    dealii::TrilinosWrappers::MPI::Vector  solution_, ghosted_, old_, older_, begin_, direction_, residual_;
    dealii::TrilinosWrappers::MPI::Vector  rate_; ///< d(u, p)/dt at t_n (one-step-theta)
    dealii::TrilinosWrappers::MPI::Vector  mesh_, mesh_old_, mesh_older_, mesh_rate_; ///< ghosted d^G, w_n
    double                                 update_length_ = 1;
    int                                    steps_done_    = 0;
    multigrid::BlockSystem                 system_;
    std::unique_ptr<AleMeshMotion<dim>>    mesh_motion_;
  };
} // namespace physics::fsi
