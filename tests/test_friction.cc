// Coulomb friction (physics/contact/coulomb_friction.h) end to end, against Coulomb's law and
// rigid-body mechanics:
//  - a block on an inclined plane (2D, dynamics; the incline is a tilted gravity on the two-block
//    mesh): above the threshold tan(theta) > mu every contact node slips with |lambda_tau| =
//    mu lambda_n, the block accelerates at g (sin theta - mu cos theta), and the energy the bodies
//    lose is the friction work sum lambda_tau . u; below it every node sticks and nothing slides;
//  - a block pushed down and sideways (3D, quasi-static): slip at the Coulomb bound in the 2D
//    tangent plane, Newton converging superlinearly once the stick/slip set has settled;
//  - one rank against all ranks (ctest runs this program on 1 and 2 ranks; the comparison only on
//    2, see CMakeLists.txt).
#include "contact/contact_problem.h"

#include <deal.II/base/mpi.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <iostream>

using namespace physics::contact;

namespace
{
  constexpr double pi = 3.14159265358979323846, g = 9.81, mu = 0.3;
  // The upper block of meshes/two_blocks_2d.geo: 0.8 x 0.4 m, density 1000 kg/m^3 (per m depth).
  constexpr double block_mass = 0.8 * 0.4 * 1000, ramp_time = 0.04;

  bool root()
  {
    return dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
  }

  std::string output(const std::string& name)
  {
    return std::string(TEST_OUTPUT_DIR) + "/" + name + "-np" +
           std::to_string(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD));
  }

  /// The upper block rests on the clamped lower one; gravity, tilted by `degrees`, grows over
  /// 0.04 s (a sudden load would make the stiff blocks bounce) and stays.
  ContactParameters incline(double degrees, int steps, const std::string& name)
  {
    const double      theta = degrees * pi / 180;
    ContactParameters p;
    p.mesh_file                        = std::string(MESH_DIR) + "/two_blocks_2d.geo";
    p.gmsh_refinement                  = 2;
    p.youngs_modulus                   = 1e8;
    p.density                          = 1000;
    p.load_type                        = "none";
    p.load_steps                       = steps;
    p.gravity                          = {g * std::sin(theta), -g * std::cos(theta)};
    p.gravity_ramp_time                = ramp_time;
    p.scheme                           = "generalized-alpha";
    p.time_step                        = 2e-3;
    p.spectral_radius                  = 1.0;
    p.friction_coefficient             = mu;
    p.solver.preset                    = "direct(superlu)";
    p.solver.newton_relative_tolerance = 1e-9;
    p.solver.newton_absolute_tolerance = 1e-7;
    p.vtk                              = false;
    p.output_directory                 = output(name);
    return p;
  }

  /// Index of the first recorded time >= t (the energies are recorded after every time step).
  std::size_t at_time(const ContactRunSummary& s, double t)
  {
    std::size_t i = 0;
    while (i + 1 < s.time.size() && s.time[i] < t - 1e-12)
      ++i;
    return i;
  }

  /// The final contact state (rank 0 holds it, gathered): active and slipping nodes, the largest
  /// | |lambda_tau| / lambda_n - mu | / mu of the slipping ones and |lambda_tau| / lambda_n of the
  /// sticking ones.
  struct FinalState
  {
    int    active = 0, slip = 0;
    double slip_deviation = 0, stick_ratio = 0;
  };
  FinalState final_state(const ContactRunSummary& s)
  {
    FinalState f;
    for (std::size_t j = 0; j < s.slip.size(); ++j)
      if (s.active[j])
        {
          const double ratio = s.tangential[j] / s.normal_pressure[j];
          ++f.active;
          if (s.slip[j])
            {
              ++f.slip;
              f.slip_deviation = std::max(f.slip_deviation, std::abs(ratio - mu) / mu);
            }
          else
            f.stick_ratio = std::max(f.stick_ratio, ratio);
        }
    return f;
  }
} // namespace

// tan(30 deg) = 0.577 > mu = 0.3: the block slides.
TEST(Friction, BlockOnInclineSlidesAboveTheCoulombThreshold)
{
  const double theta = 30 * pi / 180, a = g * (std::sin(theta) - mu * std::cos(theta));
  const auto   s = run_contact(incline(30, 60, "incline-slide"), MPI_COMM_WORLD);
  ASSERT_TRUE(s.converged) << s.failure;
  EXPECT_LT(s.max_penetration, 1e-6 * 0.4); // below 1e-6 of the block's thickness

  // Rigid sliding after the ramp: v = a (t - ramp / 2); the speed from the kinetic energy (the
  // block's elastic vibration and the lower block's add a little).
  const std::size_t i1 = at_time(s, 0.06), i2 = s.time.size() - 1;
  const double      v1  = std::sqrt(2 * s.kinetic_energy[i1] / block_mass),
               v2       = std::sqrt(2 * s.kinetic_energy[i2] / block_mass);
  const double measured = (v2 - v1) / (s.time[i2] - s.time[i1]);
  EXPECT_NEAR(measured, a, 0.02 * a) << "sliding acceleration";

  // Energy: once gravity is constant, kinetic + strain + gravity potential decreases by exactly
  // what friction dissipates (the scheme with rho_inf = 1 dissipates nothing itself).
  const std::size_t i0    = at_time(s, ramp_time);
  const auto        total = [&](std::size_t i) {
    return s.kinetic_energy[i] + s.strain_energy[i] + s.body_force_potential[i];
  };
  const double lost = total(i0) - total(i2), friction = s.friction_work[i2] - s.friction_work[i0];
  EXPECT_GT(friction, 0.0);
  EXPECT_NEAR(lost, friction, 0.01 * friction) << "energy lost vs friction work";
  // ... and that is mu N times the distance slid: mu m g cos(theta) (s(t2) - s(t0)).
  const auto   slid     = [&](std::size_t i) { return 0.5 * a * std::pow(s.time[i] - 0.5 * ramp_time, 2); };
  const double expected = mu * block_mass * g * std::cos(theta) * (slid(i2) - slid(i0));
  EXPECT_NEAR(friction, expected, 0.03 * expected) << "friction work vs mu N s";

  if (root())
    {
      const auto f = final_state(s);
      EXPECT_GT(f.active, 0);
      EXPECT_EQ(f.slip, f.active) << "every contact node slides";
      EXPECT_LT(f.slip_deviation, 1e-6) << "|lambda_tau| = mu lambda_n in slip";
      std::cout << std::defaultfloat << std::setprecision(6) << "incline 30 deg: acceleration " << measured
                << " (rigid " << a << "), energy lost " << lost << ", friction work " << friction
                << " (mu N s " << expected << "), " << f.slip << " of " << f.active
                << " nodes slip, largest | |lambda_tau| / lambda_n - mu | / mu " << f.slip_deviation << "\n";
    }
}

// tan(10 deg) = 0.176 < mu: the block sticks (an elastic shear of the blocks, no sliding).
TEST(Friction, BlockOnInclineSticksBelowTheCoulombThreshold)
{
  const auto s = run_contact(incline(10, 60, "incline-stick"), MPI_COMM_WORLD);
  ASSERT_TRUE(s.converged) << s.failure;
  // Sliding like the 30 degree block would move it by ~1 cm; it moves by the elastic shear only.
  EXPECT_LT(s.max_displacement, 1e-4);
  // The little work done while gravity grows (a few nodes slip briefly at the rims) is 1e-6 of
  // what the sliding block dissipates.
  EXPECT_LT(s.friction_work.back(), 1e-4);
  if (root())
    {
      const auto f = final_state(s);
      EXPECT_GT(f.active, 0);
      EXPECT_EQ(f.slip, 0) << "no node slides";
      EXPECT_LT(f.stick_ratio, mu);
      std::cout << std::defaultfloat << std::setprecision(6) << "incline 10 deg: " << f.active
                << " nodes stick, largest |lambda_tau| / lambda_n " << f.stick_ratio
                << ", largest displacement " << s.max_displacement << "\n";
    }
}

// 3D, quasi-static: the upper block's top face is moved down by 5 mm and sideways by (10, 5) mm.
// Every contact node slips in the 2D tangent plane at the Coulomb bound; the last Newton steps of
// each load step converge superlinearly (the exact linearization of the slip rows).
TEST(Friction, PushedBlock3DSlipsAtTheCoulombBound)
{
  ContactParameters p;
  p.dimension            = 3;
  p.mesh_file            = std::string(MESH_DIR) + "/two_blocks_3d.geo";
  p.gmsh_refinement      = 1;
  p.displacement         = {0.01, 0.005, -0.005};
  p.load_steps           = 2;
  p.friction_coefficient = mu;
  p.solver.preset        = "direct(superlu)";
  p.vtk                  = false;
  p.output_directory     = output("pushed-3d");
  const auto s           = run_contact(p, MPI_COMM_WORLD);
  ASSERT_TRUE(s.converged) << s.failure;
  for (const auto& r : s.residuals)
    {
      ASSERT_GE(r.size(), 3u);
      const std::size_t n = r.size();
      EXPECT_LT(r[n - 1] / r[n - 2], 1e-3);
      EXPECT_LT(r[n - 1] / r[n - 2], 0.1 * r[n - 2] / r[n - 3]);
    }
  if (root())
    {
      const auto f = final_state(s);
      EXPECT_GT(f.active, 0);
      EXPECT_EQ(f.slip, f.active);
      EXPECT_LT(f.slip_deviation, 1e-6);
      std::cout << std::defaultfloat << std::setprecision(6) << "pushed block 3D: " << f.slip << " of "
                << f.active << " nodes slip, largest deviation " << f.slip_deviation
                << ", Newton steps per load step " << s.newton_iterations[0] << ", " << s.newton_iterations[1]
                << "\n";
    }
}

// One rank against all ranks on the sliding block: the same steps, Newton steps, stick/slip state
// and displacements. Every rank also runs the problem alone (MPI_COMM_SELF); on one rank in all
// that would compare a run with itself, so it fails there (ctest's friction.np1 leaves it out).
TEST(Friction, OneRankAndAllRanksAgree)
{
  ASSERT_GE(dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD), 2u)
      << "compares 1 rank with all ranks: run it on 2 or more ranks";
  const int rank = dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD);
  MPI_Comm  self;
  MPI_Comm_split(MPI_COMM_WORLD, rank, 0, &self);
  const auto all = run_contact(incline(30, 25, "ranks-all"), MPI_COMM_WORLD);
  const auto one = run_contact(incline(30, 25, "ranks-one-" + std::to_string(rank)), self);
  MPI_Comm_free(&self);
  ASSERT_TRUE(all.converged);
  ASSERT_TRUE(one.converged);
  EXPECT_EQ(all.newton_iterations, one.newton_iterations);
  EXPECT_EQ(all.active_set_sizes, one.active_set_sizes);
  EXPECT_NEAR(all.displacement_l2, one.displacement_l2, 1e-8 * one.displacement_l2);
  EXPECT_NEAR(all.friction_work.back(), one.friction_work.back(), 1e-8 * one.friction_work.back());
  if (rank != 0)
    return;
  ASSERT_EQ(all.slip, one.slip);
  std::cout << std::defaultfloat << std::setprecision(10) << "1 vs "
            << dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) << " ranks: " << one.residuals.size()
            << " steps, |u| " << one.displacement_l2 << " vs " << all.displacement_l2 << ", friction work "
            << one.friction_work.back() << " vs " << all.friction_work.back() << "\n";
}
