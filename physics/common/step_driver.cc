#include "common/step_driver.h"

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace physics
{
  namespace
  {
    /// Gives the heap's free pages back to the system, once per step (after its Newton solve).
    /// A step's assemblies and AMG hierarchies are a rank's largest allocations; glibc keeps the
    /// pages they free resident wherever live small objects sit between them, and later
    /// allocations do not all fit there, so without this the resident set grows from step to
    /// step. Measured on the FSI tube at 20 k DOFs per rank, 3 time steps of 2-3 Newton steps:
    /// the 4-rank run's rank 0 (which also factors the gathered coarse level) 692 -> 664 MB peak,
    /// 1 rank 550 -> 536 MB, 210 k page faults against 104 k. Not after every Newton step: the
    /// pages given back are faulted in again by the next allocations, and on this (virtual)
    /// machine that cost 38 % more CPU time per run when done after every assembly and every
    /// solve (661 k page faults; 4 ranks: 617 MB). Once per step costs 6-8 % of the wall time of
    /// the main example here (the rings, 92 steps, 2 ranks: 83.8 / 84.1 s against 77.3 / 79.7 s),
    /// for 3 MB; again with the switch, alternating: 100.8 / 87.7 s against 85.7 / 76.1 s, for 8-10 MB
    /// of peak; on hardware without a hypervisor a page fault costs several times less. Trimming
    /// only where mallinfo2 reports more free than live memory did not help on the FSI tube
    /// (rank 0 stayed at 692 MB). `Step control/Return free memory = false` turns it off.
    void return_free_pages()
    {
#ifdef __GLIBC__
      malloc_trim(0);
#endif
    }

    /// The last step ends exactly at t_end: a remainder below this fraction of the nominal step
    /// is rounding, not a step of its own.
    constexpr double end_tolerance = 1e-10;

    /// Where a step of length `step` from `time` ends: on the grid of nominal steps where it lands
    /// there (k dt, as a run without cuts counts time, so that rounding does not accumulate), and
    /// exactly at the end time for the last one.
    double step_end(double time, double step, const StepSettings& settings)
    {
      double       t_new = std::min(time + step, settings.end_time);
      const double k     = std::round(t_new / settings.step);
      if (std::abs(t_new - k * settings.step) <= end_tolerance * settings.step)
        t_new = k * settings.step;
      if (settings.end_time - t_new <= end_tolerance * settings.step)
        t_new = settings.end_time;
      return t_new;
    }

    /// Where the driver stands after a converged step, the part of a checkpoint it owns.
    struct DriverState
    {
      double time = 0, step = 0;
      int    converged_in_a_row = 0;
    };

    void save_driver(Checkpoint& c, const DriverState& d, const StepsResult& result, const NewtonSolver& newton,
                     const JsonLinesLog& log)
    {
      c.set("driver/time", d.time);
      c.set("driver/step", d.step);
      c.set("driver/converged_in_a_row", d.converged_in_a_row);
      c.set("driver/steps", result.steps);
      c.set("driver/cuts", result.cuts);
      c.set("driver/solves", newton.solves());
      // Each converged step's Newton result (the run's summary line counts them all).
      std::vector<double> iterations, setup, solve, n_residuals, residuals, n_linear, linear;
      for (const auto& n : result.newton)
        {
          iterations.push_back(n.iterations);
          setup.push_back(n.setup_seconds);
          solve.push_back(n.solve_seconds);
          n_residuals.push_back(n.residuals.size());
          residuals.insert(residuals.end(), n.residuals.begin(), n.residuals.end());
          n_linear.push_back(n.linear_iterations.size());
          linear.insert(linear.end(), n.linear_iterations.begin(), n.linear_iterations.end());
        }
      c.set("driver/newton_iterations", iterations);
      c.set("driver/setup_seconds", setup);
      c.set("driver/solve_seconds", solve);
      c.set("driver/residual_counts", n_residuals);
      c.set("driver/residuals", residuals);
      c.set("driver/linear_counts", n_linear);
      c.set("driver/linear_iterations", linear);
      c.set_text("driver/run_log", log.content());
    }

    DriverState load_driver(const Checkpoint& c, StepsResult& result, NewtonSolver& newton, JsonLinesLog& log)
    {
      DriverState d;
      d.time               = c.number("driver/time");
      d.step               = c.number("driver/step");
      d.converged_in_a_row = static_cast<int>(c.number("driver/converged_in_a_row"));
      result.steps         = static_cast<int>(c.number("driver/steps"));
      result.cuts          = static_cast<int>(c.number("driver/cuts"));
      newton.set_solves(static_cast<int>(c.number("driver/solves")));
      const auto& iterations = c.numbers("driver/newton_iterations");
      const auto& setup = c.numbers("driver/setup_seconds");
      const auto& solve = c.numbers("driver/solve_seconds");
      const auto& n_residuals = c.numbers("driver/residual_counts");
      const auto& residuals   = c.numbers("driver/residuals");
      const auto& n_linear    = c.numbers("driver/linear_counts");
      const auto& linear      = c.numbers("driver/linear_iterations");
      std::size_t r = 0, l = 0;
      for (std::size_t k = 0; k < iterations.size(); ++k)
        {
          NewtonResult n;
          n.converged     = true;
          n.iterations    = static_cast<int>(iterations[k]);
          n.setup_seconds = setup.at(k);
          n.solve_seconds = solve.at(k);
          for (std::size_t i = 0; i < n_residuals.at(k); ++i)
            n.residuals.push_back(residuals.at(r++));
          for (std::size_t i = 0; i < n_linear.at(k); ++i)
            n.linear_iterations.push_back(static_cast<int>(linear.at(l++)));
          result.newton.push_back(std::move(n));
        }
      log.restore(c.text("driver/run_log"));
      return d;
    }
  } // namespace

  StepsResult run_steps(SteppedProblem& problem, const StepSettings& settings, NewtonSolver& newton, JsonLinesLog& log,
                        dealii::ConditionalOStream& console)
  {
    StepsResult result;
    double      time = 0, step = settings.step;
    int         cuts_in_a_row = 0, converged_in_a_row = 0, attempt = 0;
    const std::string kind = problem.checkpoint_kind();
    if (kind.empty() && (settings.checkpoint_interval > 0 || !settings.resume_from.empty()))
      throw std::invalid_argument("parameter 'Interval' / --restart (Restart): this problem class does not write "
                                  "checkpoints; set 'Interval' to 0 and drop --restart");
    if (!settings.resume_from.empty())
      {
        const std::string directory  = CheckpointSeries::resolve(settings.resume_from);
        const Checkpoint  checkpoint = Checkpoint::read(directory, kind, newton.communicator());
        problem.load_state(checkpoint);
        const DriverState d = load_driver(checkpoint, result, newton, log);
        time               = d.time;
        step               = d.step;
        converged_in_a_row = d.converged_in_a_row;
        JsonLinesLog::Line line;
        line.add("event", std::string("restarted")).add("from", directory).add("load_step", result.steps).add("time", time);
        log.write(line);
        console << "Restarted from " << directory << " after step " << result.steps << " (t = " << time << ")\n";
      }
    newton.print_header(problem);
    while (settings.end_time - time > end_tolerance * settings.step)
      {
        const double t_new = step_end(time, step, settings);
        step               = t_new - time;
        if (std::abs(step - settings.step) <= end_tolerance * settings.step)
          step = settings.step; // a nominal step passes the nominal value, not a rounded difference
        const int    number = result.steps + 1;
        problem.begin_step(t_new, step);
        auto fields = [&](JsonLinesLog::Line& line) {
          line.add("load_step", number).add("time", t_new).add("step_size", step);
          if (attempt > 0)
            line.add("attempt", attempt);
        };
        const std::string prefix = "step" + std::to_string(number) + (attempt > 0 ? "." + std::to_string(attempt) : "");
        NewtonResult      newton_result = newton.solve(problem, fields, prefix);
        if (settings.return_free_memory)
          return_free_pages();
        if (newton_result.converged)
          {
            problem.end_step(number, t_new);
            const bool last = settings.end_time - t_new <= end_tolerance * settings.step;
            problem.write_output(number, t_new, last);
            result.newton.push_back(std::move(newton_result));
            result.steps = number;
            time         = t_new;
            attempt = cuts_in_a_row = 0;
            ++converged_in_a_row;
            if (settings.growth_after > 0 && converged_in_a_row >= settings.growth_after &&
                step < settings.step * (1 - end_tolerance))
              {
                const double grown = std::min(2 * step, settings.step);
                JsonLinesLog::Line line;
                line.add("event", std::string("step_grown")).add("load_step", number)
                    .add("step_size", step).add("new_step_size", grown);
                log.write(line);
                step               = grown;
                converged_in_a_row = 0;
              }
            if (settings.checkpoint_interval > 0 && number % settings.checkpoint_interval == 0 && !last)
              {
                Checkpoint checkpoint(kind);
                problem.save_state(checkpoint);
                save_driver(checkpoint, {time, step, converged_in_a_row}, result, newton, log);
                const std::string directory =
                    CheckpointSeries(settings.checkpoint_root).write(checkpoint, number, newton.communicator());
                JsonLinesLog::Line line;
                line.add("event", std::string("checkpoint")).add("load_step", number).add("directory", directory);
                log.write(line);
              }
            continue;
          }

        // A failed attempt: back to the last converged state, half the step.
        problem.reset_step();
        ++result.cuts;
        ++attempt;
        converged_in_a_row = 0;
        const double cut   = 0.5 * step;
        const bool   give_up = ++cuts_in_a_row > settings.max_cuts || cut < settings.minimum_step * (1 - 1e-12);
        JsonLinesLog::Line line;
        line.add("event", std::string(give_up ? "run_stopped" : "step_cut")).add("load_step", number)
            .add("time", t_new).add("reason", newton_result.failure)
            .add("failed_step_size", step);
        if (!give_up)
          line.add("new_step_size", cut);
        log.write(line);
        console << "step " << number << " failed (" << newton_result.failure << "): ";
        if (give_up)
          {
            console << "no further cut (" << settings.max_cuts << " cuts in a row at most, minimum step "
                    << settings.minimum_step << "); stopping\n";
            result.failure = newton_result.failure;
            result.newton.push_back(std::move(newton_result));
            return result;
          }
        console << "step size cut from " << step << " to " << cut << "\n";
        step = cut;
      }
    result.converged = true;
    return result;
  }

  void RunSummary::record(const StepsResult& result)
  {
    converged       = result.converged;
    load_steps_done = result.steps;
    step_cuts       = result.cuts;
    failure         = result.failure;
    for (const auto& n : result.newton)
      {
        newton_iterations.push_back(n.iterations);
        residuals.push_back(n.residuals);
        linear_iterations.insert(linear_iterations.end(), n.linear_iterations.begin(), n.linear_iterations.end());
        setup_seconds += n.setup_seconds;
        solve_seconds += n.solve_seconds;
      }
  }

  std::string RunSummary::summary_line(const std::string& steps, const std::string& extra) const
  {
    int total_newton = 0, total_linear = 0, max_linear = 0;
    for (const int n : newton_iterations)
      total_newton += n;
    for (const int n : linear_iterations)
      {
        total_linear += n;
        max_linear = std::max(max_linear, n);
      }
    std::ostringstream line;
    line << "Summary: " << load_steps_done << " " << steps << " steps, " << total_newton
         << " Newton steps, GMRES iterations per Newton step: average "
         << (linear_iterations.empty() ? 0.0 : double(total_linear) / linear_iterations.size()) << ", max "
         << max_linear << "; setup " << setup_seconds << " s, solve " << solve_seconds << " s; "
         << (extra.empty() ? "" : extra + "; ") << (converged ? "converged" : "NOT converged");
    return line.str();
  }
} // namespace physics
