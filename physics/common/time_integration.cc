#include "common/time_integration.h"

#include <stdexcept>
#include <string>

namespace physics
{
  using dealii::TrilinosWrappers::MPI::Vector;

  GeneralizedAlpha::GeneralizedAlpha(double spectral_radius, double time_step)
  {
    const double rho = spectral_radius;
    if (!(rho >= 0 && rho <= 1))
      throw std::invalid_argument("parameter 'Spectral radius': expected 0 <= rho <= 1, got " + std::to_string(rho));
    if (!(time_step > 0))
      throw std::invalid_argument("parameter 'Time step': expected a positive value, got " + std::to_string(time_step));
    alpha_m_ = (2 * rho - 1) / (rho + 1);
    alpha_f_ = rho / (rho + 1);
    beta_    = 0.25 * (1 - alpha_m_ + alpha_f_) * (1 - alpha_m_ + alpha_f_);
    gamma_   = 0.5 - alpha_m_ + alpha_f_;
    dt_      = time_step;
  }

  void GeneralizedAlpha::history(const dealii::TrilinosWrappers::SparseMatrix& M, const Vector& u_old,
                                 const Vector& v_old, const Vector& a_old, const Vector& r_old, Vector& h) const
  {
    const double c_m = mass_coefficient();
    Vector       b(u_old);
    b.sadd(-c_m, -c_m * dt_, v_old);                                           // -c_m (u_n + dt v_n)
    b.add(alpha_m_ - (1 - alpha_m_) * (1 / (2 * beta_) - 1), a_old);          // + (...) a_n
    h.reinit(u_old, true);
    M.vmult(h, b);
    h.add(alpha_f_, r_old);
  }

  void GeneralizedAlpha::update(const Vector& u_new, const Vector& u_old, Vector& v, Vector& a) const
  {
    // a_{n+1} = (u_{n+1} - u_n - dt v_n)/(beta dt^2) - (1/(2 beta) - 1) a_n
    Vector a_new(u_new);
    a_new.add(-1.0, u_old, -dt_, v);
    a_new *= 1.0 / (beta_ * dt_ * dt_);
    a_new.add(-(1 / (2 * beta_) - 1), a);
    // v_{n+1} = v_n + dt ((1 - gamma) a_n + gamma a_{n+1})
    v.add(dt_ * (1 - gamma_), a, dt_ * gamma_, a_new);
    a = a_new;
  }
} // namespace physics
