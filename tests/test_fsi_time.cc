// The FSI fluid's time integrators (physics/fsi/ale_fluid.h, TimeStencil) on the fluid alone:
// the temporal order of BDF1, BDF2 and one-step-theta (theta = 1/2 and 1) on a pulsating flow
// through a square whose interior mesh moves, and one-step-theta on a sequence of unequal steps.
//
// The order is measured against the same spatial discretization (self-convergence): the
// velocity at T for dt, dt/2, dt/4 against a run with dt/64 (BDF2), so the spatial error
// drops out; tau_M without its 2/dt term here, else the stabilized spatial operator itself
// changes with dt (measured with it: the differences to the reference stay at 8-10 % of |u|
// for every scheme and dt, orders 0.2). The flow starts from rest with zero rates (the driving profile and the mesh motion
// grow like t^2), the initial rates one-step-theta starts from are then exact; with an
// inconsistent start the trapezoidal rule (theta = 1/2, no damping of the stiff modes) carries
// the wrong rate along as an undamped oscillation. Runs on 1 and 2 ranks; prints the numbers.
#include "fsi/fluid_flow.h"
#include "fsi_test_helpers.h"

#include <deal.II/base/function.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

using namespace dealii;

namespace
{
  using physics::fsi::FluidFlow;
  using physics::fsi::FluidFlowSetup;
  using physics::fsi::FluidTimeScheme;
  using Vec = TrilinosWrappers::MPI::Vector;

  const MPI_Comm comm = MPI_COMM_WORLD;

  /// g(t) = sin^2(pi t): zero value and rate at t = 0.
  double ramp(double t)
  {
    return std::pow(std::sin(M_PI * t), 2);
  }

  /// The driving velocity on the whole boundary of [0, 1]^2: u = (g(t) 4 y (1 - y), 0) (in at
  /// x = 0, out at x = 1, zero on the walls y = 0, 1).
  class PulsingProfile : public Function<2>
  {
  public:
    PulsingProfile()
        : Function<2>(3)
    {
    }
    double value(const Point<2>& X, unsigned int c) const override
    {
      return c == 0 ? ramp(get_time()) * 4 * X[1] * (1 - X[1]) : 0.0;
    }
  };

  /// The interior of the mesh moves, the boundary stays: d = 0.1 sin(pi X) sin(pi Y) g(t) (1, -0.7).
  class InteriorMotion : public Function<2>
  {
  public:
    InteriorMotion()
        : Function<2>(2)
    {
    }
    double value(const Point<2>& X, unsigned int c) const override
    {
      return 0.1 * std::sin(M_PI * X[0]) * std::sin(M_PI * X[1]) * ramp(get_time()) * (c == 0 ? 1.0 : -0.7);
    }
  };

  struct Scheme
  {
    std::string     name;
    FluidTimeScheme scheme;
    double          theta;
  };

  /// The fluid (u, p) after the steps of the sizes in `steps` (from t = 0).
  Vec run(const Scheme& scheme, std::vector<double> steps)
  {
    parallel::distributed::Triangulation<2> tria(comm);
    GridGenerator::subdivided_hyper_cube(tria, 8, 0.0, 1.0, true);
    FluidFlowSetup<2> s;
    s.model.properties = {1.0, 0.05};
    s.model.scheme     = scheme.scheme;
    s.model.theta      = scheme.theta;
    // tau without dt: the stabilized discretization in space is then the same for every dt.
    s.model.tau_with_time_step = false;
    auto profile       = std::make_shared<PulsingProfile>();
    for (types::boundary_id b = 0; b < 4; ++b)
      s.velocity[b] = profile;
    s.pressure_point = std::make_pair(Point<2>(1.0, 0.0), std::make_shared<Functions::ZeroFunction<2>>(3));
    s.mesh_motion    = std::make_shared<InteriorMotion>();
    FluidFlow<2> flow(tria, s, comm);
    flow.set_initial_state(Functions::ZeroFunction<2>(3));
    // One step at a time (the step driver takes one step size).
    fsi_test::DirectNewton newton(1e-10, comm);
    double                 time = 0;
    for (std::size_t n = 0; n < steps.size(); ++n)
      {
        time += steps[n];
        const auto result = newton.step(flow, static_cast<int>(n + 1), time, steps[n]);
        EXPECT_TRUE(result.converged) << result.failure;
      }
    return flow.owned_solution();
  }

  std::vector<double> equal_steps(double dt)
  {
    return std::vector<double>(static_cast<std::size_t>(std::lround(0.5 / dt)), dt);
  }

  /// max |u - u_ref| over the velocity DOFs (the pressure is one order lower in time for
  /// index-2 systems and not what the schemes are judged by).
  double velocity_error(const Vec& u, const Vec& reference)
  {
    double largest = 0;
    for (const auto i : u.locally_owned_elements())
      if (i % 3 != 2)
        largest = std::max(largest, std::abs(u[i] - reference[i]));
    return Utilities::MPI::max(largest, comm);
  }

  /// The reference, BDF2 with dt = 0.05 / 64, computed once for the suite (and released before
  /// MPI ends).
  class FsiFluidTime : public ::testing::Test
  {
  protected:
    static void SetUpTestSuite()
    {
      reference_ = std::make_unique<Vec>(run({"BDF2", FluidTimeScheme::bdf2, 1.0}, equal_steps(0.05 / 64)));
    }
    static void       TearDownTestSuite() { reference_.reset(); }
    static const Vec& reference() { return *reference_; }

  private:
    static std::unique_ptr<Vec> reference_;
  };
  std::unique_ptr<Vec> FsiFluidTime::reference_;

  TEST_F(FsiFluidTime, TemporalOrders)
  {
    const std::vector<std::pair<Scheme, double>> schemes = {
        {{"BDF1", FluidTimeScheme::bdf1, 1.0}, 1.0},
        {{"BDF2", FluidTimeScheme::bdf2, 1.0}, 2.0},
        {{"one-step-theta 1/2", FluidTimeScheme::one_step_theta, 0.5}, 2.0},
        {{"one-step-theta 1", FluidTimeScheme::one_step_theta, 1.0}, 1.0}};
    std::vector<double> errors_theta_one;
    for (const auto& [scheme, order] : schemes)
      {
        std::vector<double> errors;
        for (const double dt : {0.05, 0.025, 0.0125})
          errors.push_back(velocity_error(run(scheme, equal_steps(dt)), reference()));
        const double p1 = std::log2(errors[0] / errors[1]), p2 = std::log2(errors[1] / errors[2]);
        if (fsi_test::root())
          std::cout << std::setprecision(4) << scheme.name << ": max |u - u_ref| at dt = 0.05, 0.025, 0.0125: "
                    << errors[0] << ", " << errors[1] << ", " << errors[2] << "; orders " << p1 << ", " << p2
                    << "\n";
        EXPECT_NEAR(p2, order, 0.2) << scheme.name;
        EXPECT_NEAR(p1, order, 0.35) << scheme.name;
        if (scheme.scheme == FluidTimeScheme::bdf1 ||
            (scheme.scheme == FluidTimeScheme::one_step_theta && scheme.theta == 1.0))
          errors_theta_one.push_back(errors[2]);
      }
    // theta = 1 is backward Euler: the same numbers as BDF1.
    ASSERT_EQ(errors_theta_one.size(), 2u);
    EXPECT_NEAR(errors_theta_one[1], errors_theta_one[0], 1e-10 * errors_theta_one[0]);
  }

  TEST_F(FsiFluidTime, OneStepThetaOnUnequalSteps)
  {
    // Steps of 0.025 and 0.0125 alternating (and the rest to T) against the same reference: the
    // error lies between those of the equal-step runs with 0.025 and 0.0125 (the rates carry no
    // step size, so nothing needs to be re-weighted after a change of dt).
    const Scheme theta{"one-step-theta 1/2", FluidTimeScheme::one_step_theta, 0.5};
    std::vector<double> mixed;
    for (double t = 0; t < 0.5 - 1e-12;)
      {
        const double dt = mixed.size() % 2 == 0 ? 0.025 : 0.0125;
        mixed.push_back(std::min(dt, 0.5 - t));
        t += mixed.back();
      }
    const double coarse = velocity_error(run(theta, equal_steps(0.025)), reference()),
                 fine   = velocity_error(run(theta, equal_steps(0.0125)), reference()),
                 error  = velocity_error(run(theta, mixed), reference());
    if (fsi_test::root())
      std::cout << std::setprecision(4) << "one-step-theta 1/2, " << mixed.size()
                << " alternating steps of 0.025 / 0.0125: max |u - u_ref| = " << error << " (equal steps "
                << coarse << " / " << fine << ")\n";
    EXPECT_LT(error, coarse);
    EXPECT_GT(error, fine);
  }
} // namespace
