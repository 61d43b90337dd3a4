// Incompressible Newtonian fluid in arbitrary Lagrangian-Eulerian (ALE) form on a moving mesh,
// equal-order Q1/Q1 velocity/pressure with residual-based stabilization (the seeds' fluid; FSI.md).
//
// The mesh moves with the grid displacement d^G: x = X + d^G(X, t), and the grid velocity is
// w = d/dt d^G at fixed X. In the non-conservative ALE form the equations on the current domain
// Omega(t) read
//   rho (du/dt|_X + ((u - w) . grad) u) - div sigma = rho f,   div u = 0,
//   sigma = -p I + 2 mu eps(u),   eps(u) = (grad u + grad u^T) / 2,
// so the time derivative is taken at a fixed mesh node (the nodal difference of the unknowns)
// and only the convective velocity c = u - w sees the mesh motion. In time, BDF1 (backward Euler),
// BDF2 or one-step-theta at t_{n+1} (TimeStencil below), and the grid velocity with the same
// stencil, so that a uniform flow moving with a uniformly moving mesh is reproduced exactly
// (geometric conservation; test_fsi_fluid.cc). All integrals are over Omega(t_{n+1}).
//
// Galerkin weak form plus the stabilization of Tezduyar / Hughes (PSPG + SUPG + grad-div), with
// the strong momentum residual r_M = rho (du/dt + (c . grad) u) + grad p - rho f (the viscous
// term div(2 mu eps(u_h)) is dropped: it vanishes on affine Q1 cells and is O(h) elsewhere):
//   momentum, test v:   (rho (du/dt + (c . grad) u), v) + (2 mu eps(u), eps(v)) - (p, div v) - (rho f, v)
//                       + sum_K (tau_M (c . grad) v, r_M)_K            (SUPG)
//                       + sum_K (rho tau_C div u, div v)_K              (grad-div)
//                       + int_{Gamma_P} P n . v ds                      (prescribed pressure P)
//   continuity, test q: (q, div u) + sum_K (tau_M / rho grad q, r_M)_K (PSPG)
// with, per cell of size h = |K|^(1/dim) and kinematic viscosity nu = mu / rho,
//   tau_M = ((2/dt)^2 + 4 |c|^2 / h^2 + (4 nu / h^2)^2)^(-1/2)    (no 2/dt term when steady or
//                                                                   FluidModel::tau_with_time_step off),
//   tau_C = h^2 / (4 tau_M)          (-> nu in the Stokes limit, |c| h / 2 when convection rules).
//
// The geometry is that of the reference mesh pushed by d^G: with the mesh deformation gradient
// F = I + Grad d^G, grad = F^-T Grad and dx = det F dX, so the residual is a smooth function of
// both the fluid unknowns and d^G. Its derivatives come from Sacado forward AD on each cell: the
// full Newton Jacobian dR/d(u, p), including the derivatives of c, tau_M and tau_C, and, on
// request, the shape derivative dR/dd^G that the monolithic FSI Newton needs.
#pragma once

#include <deal.II/base/function.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <map>

namespace physics::fsi
{
  /// How du/dt is discretized: steady (no time derivative), BDF1 (backward Euler), BDF2 or
  /// one-step-theta.
  enum class FluidTimeScheme
  {
    steady,
    bdf1,
    bdf2,
    one_step_theta
  };

  /// The discrete time derivative at t_{n+1} of the fluid velocity, the grid displacement (the
  /// grid velocity) and the structure's interface displacement (the interface velocity):
  ///   dx/dt ~ (a0 x_{n+1} + a1 x_n + a2 x_{n-1}) / dt + a3 (dx/dt)_n,
  /// dt = t_{n+1} - t_n (all zero when steady).
  /// BDF1: 1, -1, 0, 0. BDF2 on unequal steps (after a step cut, or when the step grows back):
  /// with w = dt / dt_prev the interpolating parabola through the three states gives
  /// a0 = (1 + 2w) / (1 + w), a1 = -(1 + w), a2 = w^2 / (1 + w), a3 = 0 (3/2, -2, 1/2 for w = 1).
  /// One-step-theta in its rate form (the seeds' code's): x_{n+1} = x_n + dt (theta r_{n+1} +
  /// (1 - theta) r_n) with r = dx/dt, so a0 = 1/theta, a1 = -1/theta, a2 = 0,
  /// a3 = -(1 - theta)/theta, and the rates are carried from step to step (rate() after each
  /// step). Every other term stays at t_{n+1}: the momentum residual is the balance at t_{n+1}
  /// (its interface rows the traction at t_{n+1}, as with BDF), and theta times it is the
  /// classical theta-weighted form, the spatial terms at t_n entering through r_n (which met the
  /// balance of step n). theta = 1 is BDF1, theta = 1/2 the trapezoidal rule (second order, no
  /// numerical damping); any step-size sequence works (the rates do not depend on dt).
  struct TimeStencil
  {
    double             a0 = 0, a1 = 0, a2 = 0, a3 = 0;
    static TimeStencil of(FluidTimeScheme scheme, double step_ratio = 1.0, double theta = 1.0);
    /// The rate at t_{n+1} of x: (a0 x + a1 x_old + a2 x_older) / dt + a3 rate_old. Any vector
    /// may carry ghosts (`out`'s are filled); `out` may be `rate_old`.
    void rate(const dealii::TrilinosWrappers::MPI::Vector& x, const dealii::TrilinosWrappers::MPI::Vector& x_old,
              const dealii::TrilinosWrappers::MPI::Vector& x_older,
              const dealii::TrilinosWrappers::MPI::Vector& rate_old, double dt,
              dealii::TrilinosWrappers::MPI::Vector& out) const;
    /// The same for a number (a volume).
    double rate(double x, double x_old, double x_older, double rate_old, double dt) const
    {
      return (a0 * x + a1 * x_old + a2 * x_older) / dt + a3 * rate_old;
    }
  };

  struct FluidProperties
  {
    double density   = 1.0; ///< rho (> 0)
    double viscosity = 1.0; ///< dynamic viscosity mu (> 0)
    /// Throws std::invalid_argument naming 'Density' or 'Viscosity' for a non-positive value.
    void check() const;
  };

  /// The state the fluid residual at t_{n+1} reads. Vectors hold the locally relevant entries
  /// (ghosted); the mesh vectors live on the mesh DoFHandler (FE_Q(1)^dim on the same
  /// triangulation, cells in the same order), the fluid ones on the fluid DoFHandler
  /// (FE_Q(1)^(dim+1): velocity components, then pressure).
  template <int dim>
  struct FluidState
  {
    const dealii::TrilinosWrappers::MPI::Vector* fluid       = nullptr; ///< (u, p)_{n+1}, the iterate
    const dealii::TrilinosWrappers::MPI::Vector* fluid_old   = nullptr; ///< (u, p)_n
    const dealii::TrilinosWrappers::MPI::Vector* fluid_older = nullptr; ///< (u, p)_{n-1} (BDF2)
    const dealii::TrilinosWrappers::MPI::Vector* mesh        = nullptr; ///< d^G_{n+1} (null: mesh at rest)
    const dealii::TrilinosWrappers::MPI::Vector* mesh_old    = nullptr; ///< d^G_n
    const dealii::TrilinosWrappers::MPI::Vector* mesh_older  = nullptr; ///< d^G_{n-1} (BDF2)
    const dealii::TrilinosWrappers::MPI::Vector* fluid_rate  = nullptr; ///< d(u, p)/dt at t_n (theta); null: 0
    const dealii::TrilinosWrappers::MPI::Vector* mesh_rate   = nullptr; ///< w_n (one-step-theta); null: 0
  };

  template <int dim>
  struct FluidModel
  {
    FluidProperties properties;
    FluidTimeScheme scheme             = FluidTimeScheme::steady;
    double          time_step          = 1.0; ///< dt (> 0 unless steady)
    double          previous_time_step = 0;   ///< the step before (BDF2 on unequal steps); 0: dt
    double          theta              = 1.0; ///< one-step-theta's theta (1/2 <= theta <= 1)
    /// tau_M with its (2/dt)^2 term (the usual choice); without it the stabilized spatial
    /// discretization does not depend on dt (the seeds' code's "wo_dt" tau definitions): the
    /// temporal error alone then changes with dt, and small steps keep the PSPG pressure
    /// stabilization (with the term, tau_M -> dt/2 weakens it as dt -> 0).
    bool tau_with_time_step = true;
    /// dt / dt_prev (1 when the previous step is not known).
    double step_ratio() const { return previous_time_step > 0 ? time_step / previous_time_step : 1.0; }
    TimeStencil stencil() const { return TimeStencil::of(scheme, step_ratio(), theta); }
    const dealii::Function<dim>* body_force = nullptr; ///< f (dim components, current x), null: none
    /// Prescribed pressure P per boundary id (traction -P n on the current boundary).
    std::map<dealii::types::boundary_id, double> boundary_pressures;
  };

  /// Assembles R(u, p; d^G) over the locally owned cells through `constraints` (homogeneous
  /// constraints for the Newton increment: constrained rows get the diagonal and zero residual),
  /// and dR/d(u, p) into `jacobian` if not null, and the shape derivative dR/dd^G into
  /// `shape_derivative` if not null (rows: fluid DOFs, columns: mesh DOFs; `mesh_constraints`
  /// drops the columns the mesh problem prescribes, rows as `constraints`). Throws
  /// std::domain_error if a cell of the moved mesh is inverted (det F <= 0).
  template <int dim>
  void assemble_ale_fluid(const dealii::DoFHandler<dim>& fluid_dofs, const dealii::DoFHandler<dim>* mesh_dofs,
                          const FluidModel<dim>& model, const FluidState<dim>& state,
                          const dealii::AffineConstraints<double>& constraints,
                          dealii::TrilinosWrappers::MPI::Vector&   residual,
                          dealii::TrilinosWrappers::SparseMatrix*  jacobian,
                          dealii::TrilinosWrappers::SparseMatrix*  shape_derivative = nullptr,
                          const dealii::AffineConstraints<double>* mesh_constraints = nullptr);
} // namespace physics::fsi
