#include "common/step_driver.h"

#include <algorithm>
#include <cmath>

namespace physics
{
  namespace
  {
    /// The last step ends exactly at t_end: a remainder below this fraction of the nominal step
    /// is rounding, not a step of its own.
    constexpr double end_tolerance = 1e-10;
  } // namespace

  StepsResult run_steps(SteppedProblem& problem, const StepSettings& settings, NewtonSolver& newton, JsonLinesLog& log,
                        dealii::ConditionalOStream& console)
  {
    StepsResult result;
    double      time = 0, step = settings.step;
    int         cuts_in_a_row = 0, converged_in_a_row = 0, attempt = 0;
    newton.print_header(problem);
    while (settings.end_time - time > end_tolerance * settings.step)
      {
        if (settings.end_time - time - step < end_tolerance * settings.step)
          step = settings.end_time - time;
        step               = std::min(step, settings.end_time - time);
        const double t_new = time + step;
        const int    number = result.steps + 1;
        problem.begin_step(t_new, step);
        auto fields = [&](JsonLinesLog::Line& line) {
          line.add("load_step", number).add("time", t_new).add("step_size", step);
          if (attempt > 0)
            line.add("attempt", attempt);
        };
        const std::string prefix = "step" + std::to_string(number) + (attempt > 0 ? "." + std::to_string(attempt) : "");
        NewtonResult      newton_result = newton.solve(problem, fields, prefix);
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
            if (settings.growth_after > 0 && converged_in_a_row >= settings.growth_after && step < settings.step)
              {
                const double grown = std::min(2 * step, settings.step);
                JsonLinesLog::Line line;
                line.add("event", std::string("step_grown")).add("load_step", number)
                    .add("step_size", step).add("new_step_size", grown);
                log.write(line);
                step               = grown;
                converged_in_a_row = 0;
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
} // namespace physics
