// Implicit dynamics of the common physics layer: the generalized-alpha method of Chung and
// Hulbert (1993), shared by every problem class with inertia.
//
// The semi-discrete equation of motion M a + r(u, t) = 0 (r = internal minus external forces,
// plus constraint forces such as contact) is enforced at the generalized midpoints
//   M a_{n+1-am} + r_{n+1-af} = 0,   a_{n+1-am} = (1-am) a_{n+1} + am a_n,
//                                    r_{n+1-af} = (1-af) r(u_{n+1}, t_{n+1}) + af r(u_n, t_n),
// with the Newmark relations
//   u_{n+1} = u_n + dt v_n + dt^2 ((1/2 - beta) a_n + beta a_{n+1}),
//   v_{n+1} = v_n + dt ((1 - gamma) a_n + gamma a_{n+1}).
// Chung-Hulbert's choice from the spectral radius rho at infinite frequency (0 <= rho <= 1),
//   am = (2 rho - 1)/(rho + 1), af = rho/(rho + 1), beta = (1 - am + af)^2/4, gamma = 1/2 - am + af,
// is second-order accurate, unconditionally stable for linear problems and damps the highest
// frequencies to rho. rho = 1 gives am = af = 1/2, beta = 1/4, gamma = 1/2: no numerical
// dissipation (the trapezoidal rule, energy-conserving for linear elasticity).
//
// Newton solves for u_{n+1}; a_{n+1} is a function of it, so with
//   M a_{n+1-am} = c_m M u_{n+1} + M b_n,   c_m = (1-am)/(beta dt^2),
//   b_n = -c_m (u_n + dt v_n) + (am - (1-am)(1/(2 beta) - 1)) a_n,
// the residual is   c_m M u_{n+1} + (1-af) r(u_{n+1}) + h_n,   h_n = M b_n + af r(u_n, t_n),
// and its Jacobian  c_m M + (1-af) dr/du.  h_n is constant within a time step.
#pragma once

#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

namespace physics
{
  class GeneralizedAlpha
  {
  public:
    /// Throws std::invalid_argument naming 'Spectral radius' (0 <= rho <= 1) or 'Time step' (> 0).
    GeneralizedAlpha(double spectral_radius, double time_step);

    double alpha_m() const { return alpha_m_; }
    double alpha_f() const { return alpha_f_; }
    double beta() const { return beta_; }
    double gamma() const { return gamma_; }
    double time_step() const { return dt_; }

    /// Weight of r(u_{n+1}) in the residual: 1 - af.
    double force_weight() const { return 1.0 - alpha_f_; }
    /// c_m = d a_{n+1-am} / d u_{n+1} = (1 - am)/(beta dt^2).
    double mass_coefficient() const { return (1.0 - alpha_m_) / (beta_ * dt_ * dt_); }

    /// h_n = M b_n + af r_n (the residual's part that is constant in a time step). `M` is the
    /// unconstrained mass matrix, `r_old` = r(u_n, t_n); all vectors without ghosts.
    void history(const dealii::TrilinosWrappers::SparseMatrix& M, const dealii::TrilinosWrappers::MPI::Vector& u_old,
                 const dealii::TrilinosWrappers::MPI::Vector& v_old, const dealii::TrilinosWrappers::MPI::Vector& a_old,
                 const dealii::TrilinosWrappers::MPI::Vector& r_old, dealii::TrilinosWrappers::MPI::Vector& h) const;

    /// After convergence: v, a hold v_n, a_n on entry and v_{n+1}, a_{n+1} on return.
    void update(const dealii::TrilinosWrappers::MPI::Vector& u_new, const dealii::TrilinosWrappers::MPI::Vector& u_old,
                dealii::TrilinosWrappers::MPI::Vector& v, dealii::TrilinosWrappers::MPI::Vector& a) const;

  private:
    double alpha_m_, alpha_f_, beta_, gamma_, dt_;
  };
} // namespace physics
