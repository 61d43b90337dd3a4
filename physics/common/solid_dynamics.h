// The state and bookkeeping of a hyperelastic solid integrated in time with generalized-alpha
// (time_integration.h), for any problem class that adds its own coupling forces: the unconstrained
// consistent mass matrix, u_n / v_n / a_n, the residual part h_n that is constant in a time
// step, the weights of the Newton residual and Jacobian, and the kinetic energy.
//
// Per time step, with the loads still at t_n:  begin_step(u_n)  ->  Newton on
//   w_f r(u) + c_m M u + h_n (+ the coupling's forces at the same midpoint) = 0
// (assemble_solid(..., weights())), then end_step(u_{n+1}).
#pragma once

#include "common/checkpoint.h"

#include "common/solid_mechanics.h"
#include "common/time_integration.h"

#include <deal.II/base/index_set.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>

namespace physics
{
  template <int dim>
  class SolidDynamics
  {
  public:
    /// Assembles M (model.densities must cover every material id). Throws std::invalid_argument
    /// for an invalid spectral radius or time step.
    SolidDynamics(double spectral_radius, double time_step, const dealii::DoFHandler<dim>& dof_handler,
                  const SolidModel<dim>& model, const dealii::IndexSet& owned, const dealii::IndexSet& relevant,
                  MPI_Comm comm);

    const GeneralizedAlpha& scheme() const { return scheme_; }
    /// A new time step for the next begin_step() (a cut or regrown step of the step driver):
    /// the method's parameters depend on the spectral radius only, its weights also on dt.
    void set_time_step(double time_step) { scheme_ = GeneralizedAlpha(spectral_radius_, time_step); }
    ResidualWeights         weights() const { return {scheme_.force_weight(), scheme_.mass_coefficient()}; }
    /// Initial velocity (set entries, then compress(insert)).
    dealii::TrilinosWrappers::MPI::Vector& velocity() { return v_; }
    const dealii::TrilinosWrappers::MPI::Vector& velocity() const { return v_; }
    /// a_n (a_{n+1} after end_step); FSI's kinematic coupling reads it.
    const dealii::TrilinosWrappers::MPI::Vector& acceleration() const { return a_; }

    /// a_0 from M a_0 = -r(u_0, t_0) on the DOFs free in `constraints` (zero where constrained).
    /// Skips the solve when r vanishes (a body at rest or in rigid motion, unloaded).
    void initial_acceleration(const dealii::TrilinosWrappers::MPI::Vector& u,
                              const dealii::AffineConstraints<double>& constraints);

    /// h_n = M b_n + af r(u_n, t_n), zero in the rows constrained in `constraints` (those are no
    /// equations of motion). `u` = u_n; the model's loads must still be those of t_n.
    void begin_step(const dealii::TrilinosWrappers::MPI::Vector& u, const dealii::AffineConstraints<double>& constraints);
    const dealii::TrilinosWrappers::MPI::Vector& history() const { return h_; }

    /// v_{n+1}, a_{n+1} from the converged u_{n+1}. (All vectors here: locally owned, no ghosts.)
    void end_step(const dealii::TrilinosWrappers::MPI::Vector& u);

    double kinetic_energy() const;

    /// u_n, v_n, a_n into a checkpoint under `prefix`/ and back (h_n is rebuilt by begin_step).
    void save(Checkpoint& checkpoint, const std::string& prefix) const;
    void load(const Checkpoint& checkpoint, const std::string& prefix);

  private:
    /// r(u) through `constraints`, assembled from a ghosted copy of u.
    void residual(const dealii::TrilinosWrappers::MPI::Vector& u, const dealii::AffineConstraints<double>& constraints,
                  dealii::TrilinosWrappers::MPI::Vector& r) const;

    double                                spectral_radius_;
    GeneralizedAlpha                      scheme_;
    const dealii::DoFHandler<dim>&        dof_handler_;
    const SolidModel<dim>&                model_;
    dealii::IndexSet                      owned_, relevant_;
    MPI_Comm                              comm_;
    dealii::DynamicSparsityPattern        pattern_;
    dealii::TrilinosWrappers::SparseMatrix mass_; ///< unconstrained
    dealii::TrilinosWrappers::MPI::Vector u_old_, v_, a_, h_;
  };
} // namespace physics
