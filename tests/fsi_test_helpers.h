// Shared pieces of the FSI fluid tests (test_fsi_fluid.cc, test_fsi_time.cc): Newton with
// direct(superlu) on the fluid alone, through the step driver or one given step at a time.
#pragma once

#include "common/newton_solver.h"
#include "common/step_driver.h"

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include <iostream>

namespace fsi_test
{
  inline bool root(MPI_Comm comm = MPI_COMM_WORLD)
  {
    return dealii::Utilities::MPI::this_mpi_process(comm) == 0;
  }

  /// Newton (relative tolerance `tolerance` on both fields, 15 iterations) with direct(superlu),
  /// silent, with a log that is not written.
  class DirectNewton
  {
  public:
    explicit DirectNewton(double tolerance = 1e-10, MPI_Comm comm = MPI_COMM_WORLD)
        : console_(std::cout, false)
        , timer_(console_, dealii::TimerOutput::never, dealii::TimerOutput::wall_times)
        , newton_(settings(tolerance), multigrid::load_preset("direct(superlu)"), {}, log_, console_, timer_, comm)
    {
    }

    /// The step driver over the steps of `steps`.
    physics::StepsResult run(physics::SteppedProblem& problem, const physics::StepSettings& steps)
    {
      return physics::run_steps(problem, steps, newton_, log_, console_);
    }

    /// One step of length `step` ending at `time` (no cuts): begin_step, Newton, end_step.
    physics::NewtonResult step(physics::SteppedProblem& problem, int number, double time, double step)
    {
      problem.begin_step(time, step);
      auto result = newton_.solve(problem, [](physics::JsonLinesLog::Line&) {}, "");
      if (result.converged)
        problem.end_step(number, time);
      return result;
    }

  private:
    static physics::NewtonSettings settings(double tolerance)
    {
      physics::NewtonSettings s;
      s.max_iterations = 15;
      s.tolerances     = {{1e-13, tolerance}, {1e-13, tolerance}};
      return s;
    }

    physics::JsonLinesLog      log_;
    dealii::ConditionalOStream console_;
    dealii::TimerOutput        timer_;
    physics::NewtonSolver      newton_;
  };

  /// Runs `problem` over the steps of `steps` with DirectNewton; returns the driver's result.
  inline physics::StepsResult solve(physics::SteppedProblem& problem, const physics::StepSettings& steps,
                                    double tolerance = 1e-10, MPI_Comm comm = MPI_COMM_WORLD)
  {
    return DirectNewton(tolerance, comm).run(problem, steps);
  }
} // namespace fsi_test
