// Coulomb friction at one active slave node in the normal-tangential form of the semi-smooth
// Newton method (Hueber, Stadler & Wohlmuth 2008; Gitterle, Popp, Gee & Wall 2010), for any
// scalar type T (double, or Sacado's forward AD type for the exact linearization).
//
// Conventions of mortar_contact.h: the traction on the slave body is -lambda_j, lambda_n =
// n_j . lambda_j > 0 is the contact pressure, v_j = sum_l M_jl x_l - sum_k D_jk x_k. The weighted
// relative slip of the slave body against the master body in the current step is
//     u_m = -tau_m . (v_j - v_j^start),  v_j^start = the same sums with the current D, M and the
// positions at the start of the step (the "non-objective" slip of Gitterle et al., exact for the
// sliding of a flat interface), m = 1 .. dim-1 over the nodal tangents tau_m.
// Friction opposes the slip of the slave body: the tangential multiplier lambda_tau (components
// tau_m . lambda_j) points along the slip. With the trial traction
//     xi = lambda_tau + c_t u / w_j             (w_j = sum_k D_jk: u / w_j is a length)
// and the Coulomb bound b = mu (lambda_n - c_n g~_j / w_j) (> 0 on an active node), the
// frictional complementarity function is zero exactly when Coulomb's law holds:
//   stick (|xi| <= b):  C_m = u_m                              (no relative slip in the step)
//   slip  (|xi| >  b):  C_m = lambda_tau,m - mu lambda_n xi_m / |xi|
//                                                  (|lambda_tau| = mu lambda_n, along the slip).
// At a solution of the slip rows u = |u| xi / |xi|-direction, so lambda_tau and u point the same
// way and lambda_tau . u = mu lambda_n |u| >= 0 is the energy dissipated at the node in the step.
// The solution does not depend on c_t (it only steers the Newton iteration), just as it does not
// depend on c_n. In 2D the slip row is lambda_tau - mu lambda_n sign(xi): linear in lambda.
// mu = 0 gives lambda_tau = 0, the frictionless rows.
#pragma once

#include "common/mortar_integration.h"

#include <array>

namespace physics::contact
{
  using namespace physics::mortar; // the mortar integration shared with the FSI class (common/)
  struct FrictionLaw
  {
    double coefficient = 0.0; ///< mu >= 0
    double c_t         = 1.0; ///< tangential complementarity parameter (stiffness / length)
    double c_n         = 1.0; ///< normal complementarity parameter (stiffness / length)
  };

  /// The tangential rows of one active slave node and whether it slips.
  template <typename T, int dim>
  struct TangentialRows
  {
    std::array<T, dim - 1> residual;
    bool                   slip = false;
    /// Weighted slip u_m of the step and tangential multiplier lambda_tau,m (for output and the
    /// dissipated energy lambda_tau . u).
    std::array<T, dim - 1> slip_increment, tangential_multiplier;
  };

  /// Coulomb's law at an active node: `frame` = (n, tau_1, ..): the nodal unit normal and tangents,
  /// `lambda` the node's multiplier (Cartesian), `dv` = v_j - v_j^start, `w` = w_j, `gap_over_weight`
  /// = g~_j / w_j (only in the stick/slip decision, not differentiated).
  template <typename T, int dim>
  TangentialRows<T, dim> coulomb_rows(const std::array<Point<T, dim>, dim>& frame,
                                      const Point<T, dim>& lambda, const Point<T, dim>& dv, const T& w,
                                      double gap_over_weight, const FrictionLaw& law)
  {
    TangentialRows<T, dim> rows;
    const T                lambda_n = dot<T, dim>(frame[0], lambda);
    std::array<T, dim - 1> xi;
    double                 xi_norm2 = 0.0, reversal = 0.0;
    for (int m = 1; m < dim; ++m)
      {
        rows.tangential_multiplier[m - 1] = dot<T, dim>(frame[m], lambda);
        rows.slip_increment[m - 1]        = -dot<T, dim>(frame[m], dv);
        xi[m - 1] = rows.tangential_multiplier[m - 1] + law.c_t * rows.slip_increment[m - 1] / w;
        xi_norm2 += value_of(xi[m - 1]) * value_of(xi[m - 1]);
        reversal += value_of(xi[m - 1]) * value_of(rows.tangential_multiplier[m - 1]);
      }
    // An iterate whose trial traction points against the current tangential multiplier (xi .
    // lambda_tau < 0) would reverse the slip direction in one jump; it takes the stick rows
    // instead, since a node that reverses passes through stick. This changes only the Newton path:
    // at a solution in slip xi . lambda_tau = mu lambda_n |xi| > 0. (Without it, nodes near the
    // stick/slip boundary flip their direction back and forth for large c_t.)
    // A node on the Coulomb limit with no slip yet (|xi| = |lambda_tau| = bound up to round-off, as
    // every node that slipped in the previous step is at the start of the next) counts as slipping:
    // it goes on sliding unless the solve says otherwise.
    const double bound = law.coefficient * (value_of(lambda_n) - law.c_n * gap_over_weight);
    const double limit = bound * (1.0 - 1e-8);
    rows.slip = law.coefficient > 0.0 ? xi_norm2 > limit * limit && bound > 0.0 && reversal >= 0.0 : true;
    if (!rows.slip)
      {
        rows.residual = rows.slip_increment;
        return rows;
      }
    if (law.coefficient == 0.0) // frictionless: lambda_tau = 0 (xi may vanish)
      {
        rows.residual = rows.tangential_multiplier;
        return rows;
      }
    T xi_norm2_t = xi[0] * xi[0];
    for (int m = 1; m < dim - 1; ++m)
      xi_norm2_t += xi[m] * xi[m];
    const T xi_norm = sqrt_of(xi_norm2_t);
    for (int m = 0; m < dim - 1; ++m)
      rows.residual[m] = rows.tangential_multiplier[m] - law.coefficient * lambda_n * xi[m] / xi_norm;
    return rows;
  }
} // namespace physics::contact
