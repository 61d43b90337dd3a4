// Coulomb's law at one node (physics/contact/coulomb_friction.h) on its own: the stick/slip
// decision, that the slip rows vanish exactly on Coulomb's law, the AD derivatives of both row
// kinds against central finite differences (3D, all inputs: multiplier, frame, slip, weight), and
// the two choices that steer the Newton path (on-the-limit nodes slip, a reversal sticks).
#include "contact/coulomb_friction.h"

#include <Sacado.hpp>
#include <gtest/gtest.h>

#include <cmath>

using namespace physics::contact;
using AD = Sacado::Fad::DFad<double>;

namespace
{
  /// A node with normal n = (0, 0, 1) in a tangent frame rotated by an angle; 8 scalar inputs:
  /// lambda (3), the frame's angle (1), the slip sums s = v - v^start (3), w (1).
  constexpr int n_inputs = 8;

  template <typename T>
  std::array<Point<T, 3>, 3> frame(const T& angle)
  {
    using std::cos;
    using std::sin;
    std::array<Point<T, 3>, 3> f;
    f[0] = {{T(0.0), T(0.0), T(1.0)}};
    f[1] = {{cos(angle), sin(angle), T(0.0)}};
    f[2] = {{-sin(angle), cos(angle), T(0.0)}};
    return f;
  }

  template <typename T>
  TangentialRows<T, 3> rows(const std::array<T, n_inputs>& x, const FrictionLaw& law)
  {
    const Point<T, 3> lambda{{x[0], x[1], x[2]}}, slip{{x[4], x[5], x[6]}};
    return coulomb_rows<T, 3>(frame<T>(x[3]), lambda, slip, x[7], 0.0, law);
  }

  /// Largest relative difference between the AD derivatives of both rows and central differences.
  double derivative_error(const std::array<double, n_inputs>& x, const FrictionLaw& law, bool expect_slip)
  {
    std::array<AD, n_inputs> ad;
    for (int i = 0; i < n_inputs; ++i)
      ad[i] = AD(n_inputs, i, x[i]);
    const auto exact = rows<AD>(ad, law);
    EXPECT_EQ(exact.slip, expect_slip);
    double error = 0, scale = 0;
    for (int i = 0; i < n_inputs; ++i)
      {
        const double h  = 1e-6 * std::max(1.0, std::abs(x[i]));
        auto         xp = x, xm = x;
        xp[i] += h;
        xm[i] -= h;
        const auto rp = rows<double>(xp, law), rm = rows<double>(xm, law);
        EXPECT_EQ(rp.slip, expect_slip); // the same branch on both sides
        for (int m = 0; m < 2; ++m)
          {
            const double fd = (rp.residual[m] - rm.residual[m]) / (2 * h);
            error           = std::max(error, std::abs(fd - exact.residual[m].dx(i)));
            scale           = std::max(scale, std::abs(exact.residual[m].dx(i)));
          }
      }
    return error / scale;
  }

  const FrictionLaw law{0.3, 2.0, 5.0}; // mu, c_t, c_n
} // namespace

// Slip: the weighted slip u = -tau . s points along tau_1 + tau_2; the trial traction leaves the
// cone. At lambda_tau = mu lambda_n (u / |u|) the rows vanish: Coulomb's law in slip.
TEST(CoulombFriction, SlipRowsVanishOnCoulombsLaw)
{
  const double angle = 0.4, lambda_n = 2.0, w = 0.5;
  const auto   f = frame<double>(angle);
  // s = -(tau_1 + 2 tau_2) * 0.1: u = (0.1, 0.2), direction (1, 2) / sqrt(5)
  std::array<double, n_inputs> x{};
  for (int d = 0; d < 3; ++d)
    {
      x[4 + d] = -(f[1][d] + 2 * f[2][d]) * 0.1;
      x[d]     = lambda_n * f[0][d] + 0.3 * lambda_n * (f[1][d] + 2 * f[2][d]) / std::sqrt(5.0);
    }
  x[3]         = angle;
  x[7]         = w;
  const auto r = rows<double>(x, law);
  EXPECT_TRUE(r.slip);
  EXPECT_NEAR(r.residual[0], 0.0, 1e-14);
  EXPECT_NEAR(r.residual[1], 0.0, 1e-14);
  // dissipation lambda_tau . u = mu lambda_n |u| > 0
  const double work =
      r.tangential_multiplier[0] * r.slip_increment[0] + r.tangential_multiplier[1] * r.slip_increment[1];
  EXPECT_NEAR(work, 0.3 * lambda_n * std::sqrt(0.05), 1e-14);
}

// Stick: inside the cone the rows are the weighted slip itself.
TEST(CoulombFriction, StickInsideTheCone)
{
  std::array<double, n_inputs> x{{0.1, 0.05, 2.0, 0.3, 1e-3, -2e-3, 0.0, 0.5}};
  const auto                   r = rows<double>(x, law);
  EXPECT_FALSE(r.slip);
  EXPECT_EQ(r.residual[0], r.slip_increment[0]);
  EXPECT_EQ(r.residual[1], r.slip_increment[1]);
}

TEST(CoulombFriction, DerivativesMatchFiniteDifferences)
{
  // slip: far outside the cone, lambda_tau along the slip
  EXPECT_LT(derivative_error({{0.5, 0.4, 2.0, 0.3, -0.3, -0.2, 0.05, 0.5}}, law, true), 1e-7);
  // stick
  EXPECT_LT(derivative_error({{0.1, 0.05, 2.0, 0.3, 1e-3, -2e-3, 0.0, 0.5}}, law, false), 1e-7);
}

// A node exactly on the Coulomb limit with no slip yet slips (round-off must not split such nodes);
// a trial traction against the current tangential multiplier takes the stick rows.
TEST(CoulombFriction, NewtonPathChoices)
{
  const double                 lambda_n = 2.0;
  std::array<double, n_inputs> on_limit{{0.3 * lambda_n, 0.0, lambda_n, 0.0, 0.0, 0.0, 0.0, 0.5}};
  EXPECT_TRUE(rows<double>(on_limit, law).slip);
  on_limit[0] *= 1.0 - 1e-12; // round-off below the limit
  EXPECT_TRUE(rows<double>(on_limit, law).slip);
  on_limit[0] *= 0.99; // clearly inside
  EXPECT_FALSE(rows<double>(on_limit, law).slip);
  // lambda_tau = +0.5 tau_1, slip u = -tau_1 large: xi = 0.5 - 2 * 1 / 0.5 < 0, |xi| > mu lambda_n
  std::array<double, n_inputs> reversal{{0.5, 0.0, lambda_n, 0.0, 1.0, 0.0, 0.0, 0.5}};
  EXPECT_FALSE(rows<double>(reversal, law).slip);
  // frictionless: always the slip rows lambda_tau = 0
  const FrictionLaw frictionless{0.0, 2.0, 5.0};
  const auto        r = rows<double>(reversal, frictionless);
  EXPECT_TRUE(r.slip);
  EXPECT_EQ(r.residual[0], 0.5);
}
