// The load/time-step driver every problem class shares: pseudo-time (quasi-static load factor
// in [0, 1]) or physical time (dynamics) advanced in steps, each solved by the NewtonSolver, with
// adaptive step cutting:
//
//   t = 0, dt = dt_nominal
//   while t < t_end:
//     dt = min(dt, t_end - t);  problem.begin_step(t + dt, dt);  Newton
//     converged: problem.end_step(...); output; t += dt;
//                after `growth_after` converged steps in a row at a cut step, dt = min(2 dt, dt_nominal)
//     failed:    problem.reset_step();  dt = dt / 2   (the log says why; at most `max_cuts`
//                halvings in a row and never below `minimum_step`, else the run stops unconverged)
//
// Checkpoints (checkpoint.h): every `checkpoint_interval` converged steps the problem's state,
// the driver's counters and the run log so far go to checkpoint_root/step_NNNNNN; a run given
// `resume_from` starts from there instead of t = 0, with the log as it was at that step plus a
// "restarted" event, and continues exactly as the uninterrupted run did.
//
// A step cut is the remedy for everything Newton cannot cure from where it stands: a too large
// load increment (divergence, an inverted element), an active-set change that makes a linear
// solve fail, a time step too coarse for an impact.
#pragma once

#include "common/checkpoint.h"
#include "common/newton_solver.h"

#include <string>
#include <vector>

namespace physics
{
  struct StepSettings
  {
    double end_time = 1.0;      ///< quasi-static: load factor 1; dynamics: the final time
    double step     = 1.0;      ///< nominal step
    double minimum_step = 0.0;  ///< no cut below this (absolute)
    int    max_cuts     = 5;    ///< halvings in a row of one step
    int    growth_after = 2;    ///< converged steps in a row before a cut step is doubled (0: never)
    int         checkpoint_interval = 0; ///< converged steps between checkpoints (0: none)
    std::string checkpoint_root;         ///< where they go (the output directory's restart/)
    std::string resume_from;             ///< a checkpoint (or a checkpoint_root) to resume from
    bool        return_free_memory = true; ///< malloc_trim after each step's Newton solve (step_driver.cc)
  };

  /// A NonlinearProblem that is advanced in load/time steps.
  class SteppedProblem : public NonlinearProblem
  {
  public:
    /// Sets the loads (and dynamics history) of the step that ends at `time` (length `step`);
    /// the state of the previous step's end must stay recoverable for reset_step().
    virtual void begin_step(double time, double step) = 0;
    /// Back to the state before begin_step (a failed step).
    virtual void reset_step() = 0;
    /// Accepts the converged step (dynamics: velocities, accelerations, energies). `number`
    /// counts converged steps from 1.
    virtual void end_step(int number, double time) = 0;
    /// Output of a converged step; `last` marks the final one.
    virtual void write_output(int number, double time, bool last) = 0;

    /// Checkpoint/restart: what problem this is (class, dimension, sizes; a restart must find
    /// the same), or "" for a class that cannot restart.
    virtual std::string checkpoint_kind() const { return ""; }
    /// The state after a converged step (with end_step and write_output done): everything
    /// begin_step of the next step and the run's output and summary depend on.
    virtual void save_state(Checkpoint& /*checkpoint*/) const {}
    /// Back to the state save_state stored (on a freshly set-up problem).
    virtual void load_state(const Checkpoint& /*checkpoint*/) {}
  };

  struct StepsResult
  {
    bool                      converged = false;
    int                       steps     = 0; ///< converged steps
    int                       cuts      = 0; ///< failed attempts (each followed by a cut)
    std::vector<NewtonResult> newton;        ///< per converged step, and the last failed one
    std::string               failure;       ///< why the run stopped (empty if it finished)
  };

  /// What every problem class's run summary reports about its steps (the classes add their
  /// physics' final state).
  struct RunSummary
  {
    bool                             converged = true;
    int                              load_steps_done = 0; ///< converged load/time steps
    int                              step_cuts       = 0; ///< failed attempts, each retried with half the step
    std::string                      failure;             ///< why the run stopped (empty: it finished)
    std::vector<int>                 newton_iterations;   ///< per step
    std::vector<std::vector<double>> residuals;           ///< per step: combined residual norm per iterate
    std::vector<int>                 linear_iterations;   ///< per solve, all steps
    double                           setup_seconds = 0, solve_seconds = 0;

    /// Fills every field from the driver's result.
    void record(const StepsResult& result);
    /// The apps' closing line, the same in every app (tests and scripts match it):
    ///   "Summary: N <steps> steps, M Newton steps, GMRES iterations per Newton step: average A,
    ///    max X; setup S s, solve T s[; <extra>]; converged" (or "NOT converged").
    std::string summary_line(const std::string& steps, const std::string& extra = "") const;
  };

  /// Runs all steps. Every attempt's log lines carry "load_step" (the number the step gets when it
  /// converges), "time", "step_size" and "attempt"; a failed attempt adds an event line
  /// {"event": "step_cut", "reason": ..., "failed_step_size": ..., "new_step_size": ...}.
  StepsResult run_steps(SteppedProblem& problem, const StepSettings& settings, NewtonSolver& newton, JsonLinesLog& log,
                        dealii::ConditionalOStream& console);
} // namespace physics
