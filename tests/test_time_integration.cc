// Generalized-alpha (physics/common/time_integration.h) on the linear oscillator u'' + w^2 u = 0:
// Chung-Hulbert's coefficients, second-order accuracy, exact energy conservation for rho_inf = 1
// and the damping of unresolved modes to rho_inf.
#include "common/time_integration.h"

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <gtest/gtest.h>

#include <cmath>

namespace
{
  using dealii::TrilinosWrappers::MPI::Vector;

  /// One degree of freedom with mass 1 and stiffness w^2, advanced by the same calls a finite
  /// element problem makes: h_n from history(), the (here linear) solve of
  /// c_m M u + (1 - af) K u + h_n = 0, then update().
  struct Oscillator
  {
    Oscillator(double omega, double rho, double dt)
        : scheme(rho, dt)
        , w2(omega * omega)
    {
      dealii::IndexSet all(1);
      all.add_index(0);
      u.reinit(all, MPI_COMM_SELF);
      v.reinit(all, MPI_COMM_SELF);
      a.reinit(all, MPI_COMM_SELF);
      dealii::DynamicSparsityPattern pattern(1, 1);
      pattern.add(0, 0);
      M.reinit(all, all, pattern, MPI_COMM_SELF);
      M.set(0, 0, 1.0);
      M.compress(dealii::VectorOperation::insert);
      u[0] = 1.0;
      a[0] = -w2; // equilibrium at t = 0
    }

    void step()
    {
      Vector r_old(u), h, u_old(u);
      r_old *= w2;
      scheme.history(M, u, v, a, r_old, h);
      u[0] = -h[0] / (scheme.mass_coefficient() + scheme.force_weight() * w2);
      scheme.update(u, u_old, v, a);
    }

    double energy() const { return 0.5 * v[0] * v[0] + 0.5 * w2 * u[0] * u[0]; }

    physics::GeneralizedAlpha      scheme;
    double                         w2;
    Vector                         u, v, a;
    dealii::TrilinosWrappers::SparseMatrix M;
  };

  TEST(GeneralizedAlpha, ChungHulbertCoefficients)
  {
    const physics::GeneralizedAlpha trapezoidal(1.0, 0.1);
    EXPECT_DOUBLE_EQ(trapezoidal.alpha_m(), 0.5);
    EXPECT_DOUBLE_EQ(trapezoidal.alpha_f(), 0.5);
    EXPECT_DOUBLE_EQ(trapezoidal.beta(), 0.25);
    EXPECT_DOUBLE_EQ(trapezoidal.gamma(), 0.5);
    const physics::GeneralizedAlpha strongest(0.0, 0.1);
    EXPECT_DOUBLE_EQ(strongest.alpha_m(), -1.0);
    EXPECT_DOUBLE_EQ(strongest.alpha_f(), 0.0);
    EXPECT_DOUBLE_EQ(strongest.beta(), 1.0);
    EXPECT_DOUBLE_EQ(strongest.gamma(), 1.5);
    EXPECT_THROW(physics::GeneralizedAlpha(1.5, 0.1), std::invalid_argument);
    EXPECT_THROW(physics::GeneralizedAlpha(0.5, 0.0), std::invalid_argument);
  }

  TEST(GeneralizedAlpha, SecondOrderAccurate)
  {
    const double omega = 2 * M_PI;
    for (const double rho : {1.0, 0.8, 0.5})
      {
        std::vector<double> errors;
        for (const int n : {20, 40, 80, 160})
          {
            Oscillator o(omega, rho, 1.0 / n);
            for (int i = 0; i < n; ++i)
              o.step();
            // state error (u, v / w): the phase error shows here at first power
            const double eu = o.u[0] - std::cos(omega), ev = (o.v[0] + omega * std::sin(omega)) / omega;
            errors.push_back(std::hypot(eu, ev));
          }
        for (std::size_t k = 1; k < errors.size(); ++k)
          {
            const double order = std::log2(errors[k - 1] / errors[k]);
            EXPECT_GT(order, 1.9) << "rho " << rho << ", refinement " << k;
            EXPECT_LT(order, 2.1) << "rho " << rho << ", refinement " << k;
          }
      }
  }

  TEST(GeneralizedAlpha, TrapezoidalRuleConservesEnergy)
  {
    Oscillator   o(2 * M_PI, 1.0, 0.37); // large step: conservation is not an accuracy effect
    const double e0 = o.energy();
    for (int i = 0; i < 200; ++i)
      {
        o.step();
        EXPECT_NEAR(o.energy(), e0, 1e-12 * e0);
      }
  }

  TEST(GeneralizedAlpha, DampsUnresolvedModesToSpectralRadius)
  {
    // w dt = 1e4: the amplification matrix's eigenvalues have modulus rho_inf (a double
    // eigenvalue, so |u_n| ~ n rho^n: compare steps 40 and 80).
    for (const double rho : {0.3, 0.5, 0.8})
      {
        Oscillator o(1e4, rho, 1.0);
        double     u40 = 0;
        for (int i = 1; i <= 80; ++i)
          {
            o.step();
            if (i == 40)
              u40 = std::abs(o.u[0]);
          }
        const double per_step = std::pow(std::abs(o.u[0]) / u40, 1.0 / 40);
        EXPECT_NEAR(per_step, rho, 0.03 + 0.05 * rho) << "rho " << rho;
      }
    // rho_inf = 1 keeps even this mode's energy
    Oscillator o(1e4, 1.0, 1.0);
    for (int i = 0; i < 80; ++i)
      o.step();
    EXPECT_NEAR(o.energy(), 0.5 * 1e8, 1e-6 * 0.5 * 1e8);
  }
} // namespace

int main(int argc, char** argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
