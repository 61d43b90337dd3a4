#include "common/newton_solver.h"

#include "common/solver_parameters.h"

#include "block_preconditioner.h"
#include "block_system_io.h"

#include <Xpetra_MultiVectorFactory.hpp>

#include <deal.II/base/timer.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>

namespace physics
{
  NewtonSolver::NewtonSolver(NewtonSettings settings, multigrid::Preset preset, multigrid::SolveOptions options,
                             JsonLinesLog& log, dealii::ConditionalOStream& console, dealii::TimerOutput& timer,
                             MPI_Comm comm)
      : settings_(std::move(settings))
      , preset_(std::move(preset))
      , options_(options)
      , log_(log)
      , console_(console)
      , timer_(timer)
      , comm_(comm)
  {
    if (settings_.export_aggregates && !multigrid::builds_blocked_hierarchy(preset_))
      throw multigrid::InputError(
          "Output/Export aggregates: preset '" + preset_.name + "' (kind " + preset_.kind +
          ") builds no blocked AMG hierarchy whose aggregates could be written; use a "
          "saddle-point or fully coupled preset, or set it to false");
  }

  const FieldTolerance& NewtonSolver::tolerance(std::size_t field) const
  {
    return field < settings_.tolerances.size() ? settings_.tolerances[field] : default_tolerance_;
  }

  void NewtonSolver::print_header(const NonlinearProblem& problem) const
  {
    console_ << "  step newton   |residual|";
    for (const auto& name : problem.field_names())
      console_ << std::setw(12) << ("|r_" + name.substr(0, 7) + "|");
    console_ << problem.console_header() << "  GMRES  setup[s] solve[s]\n";
  }

  bool NewtonSolver::fields_converged(const std::vector<double>& norms, const std::vector<double>& reference) const
  {
    for (std::size_t f = 0; f < norms.size(); ++f)
      if (!(norms[f] <= tolerance(f).absolute || norms[f] <= tolerance(f).relative * reference[f]))
        return false;
    return true;
  }

  std::string NewtonSolver::residual_failure(const std::vector<double>& norms, const std::vector<double>& reference,
                                             const std::vector<std::string>& names) const
  {
    for (std::size_t f = 0; f < norms.size(); ++f)
      {
        std::ostringstream why;
        if (!std::isfinite(norms[f]))
          why << "the " << names[f] << " residual is not finite";
        else if (!reference.empty() && norms[f] > settings_.divergence_factor * divergence_scale(reference[f], f))
          why << "Newton diverged: the " << names[f] << " residual grew from " << reference[f] << " to " << norms[f];
        if (!why.str().empty())
          return why.str();
      }
    return "";
  }

  double NewtonSolver::divergence_scale(double reference, std::size_t field) const
  {
    // Growth is measured from at least the norm at which the relative tolerance stops
    // mattering, tol_abs / tol_rel (a field may be near zero until then).
    const auto& t = tolerance(field);
    return std::max(reference, t.absolute / t.relative);
  }

  double NewtonSolver::merit(const std::vector<double>& norms, const std::vector<double>& reference) const
  {
    double phi = 0;
    for (std::size_t f = 0; f < norms.size(); ++f)
      {
        const double s = std::max(reference[f], tolerance(f).absolute);
        phi += (norms[f] / s) * (norms[f] / s);
      }
    return phi;
  }

  std::string NewtonSolver::build_preconditioner(const multigrid::BlockSystem& system,
                                                 const std::string& aggregates_path, std::uint64_t state)
  {
    preconditioner_.reset();
    try
      {
        dealii::TimerOutput::Scope scope(timer_, "preconditioner setup");
        multigrid::SetupOptions    options;
        options.keep_aggregates = settings_.export_aggregates;
        options.keep_transfers  = settings_.reuse_preconditioner == PreconditionerReuse::transfers;
        // The fully coupled preset's smoother check is a check of the preset: the run's first set-up.
        options.check_level_smoother = !level_smoother_checked_;
        preconditioner_         = std::make_unique<multigrid::BlockPreconditioner>(system, preset_, options);
        level_smoother_checked_ = true;
      }
    catch (const multigrid::InputError&)
      {
        throw; // a preset that cannot work is bad input, not a numerical failure
      }
    catch (const std::exception& e)
      {
        std::string what = e.what();
        what             = what.substr(0, what.find('\n'));
        console_ << "\n";
        return "the preconditioner set-up failed (" + what.substr(0, 200) + ")";
      }
    preconditioner_state_ = state;
    if (!aggregates_path.empty())
      multigrid::write_aggregates(system, preconditioner_->aggregates(), aggregates_path);
    return "";
  }

  bool NewtonSolver::refresh_preconditioner(const multigrid::BlockSystem& system)
  {
    try
      {
        dealii::TimerOutput::Scope scope(timer_, "preconditioner setup");
        return preconditioner_->refresh(system);
      }
    catch (const std::exception&)
      {
        // The hierarchy is half set up: a fresh one follows (build_preconditioner reports what
        // goes wrong with it).
        preconditioner_.reset();
        return false;
      }
  }

  std::string NewtonSolver::solve_linear(const multigrid::BlockSystem& system, multigrid::MultiVector& dx,
                                         double step_residual, JsonLinesLog::Line& line, NewtonResult& result,
                                         const std::string& aggregates_path, std::uint64_t state)
  {
    // A kept preconditioner approximates the inverse of an earlier Newton matrix of this step with
    // the same active set; GMRES still solves the new system, and where it does not converge with
    // it the solve is repeated with a preconditioner of the new matrix. Kept transfers give a
    // hierarchy of the new matrix on the old aggregates (its set-up without the aggregation).
    const auto reuse      = settings_.reuse_preconditioner;
    const bool same_state = preconditioner_ && preconditioner_state_ == state;
    bool       reused     = reuse == PreconditionerReuse::whole && same_state;
    const bool refreshed =
        reuse == PreconditionerReuse::transfers && same_state && refresh_preconditioner(system);
    if (!reused && !refreshed)
      if (const auto failure = build_preconditioner(system, aggregates_path, state); !failure.empty())
        return failure;
    bool                   kept = reused || refreshed;
    multigrid::SolveReport report;
    {
      dealii::TimerOutput::Scope scope(timer_, "linear solve");
      report = multigrid::solve(system, *preconditioner_, dx, options_);
    }
    if (kept && !report.converged)
      {
        line.add("reused_preconditioner_iterations", report.iterations);
        const double first_setup = report.preconditioner.setup_seconds;
        reused = kept = false;
        if (const auto failure = build_preconditioner(system, aggregates_path, state); !failure.empty())
          return failure;
        const double first_seconds = report.solve_seconds;
        {
          dealii::TimerOutput::Scope scope(timer_, "linear solve");
          report = multigrid::solve(system, *preconditioner_, dx, options_);
        }
        report.solve_seconds += first_seconds;
        report.preconditioner.setup_seconds += refreshed ? first_setup : 0.0;
      }
    if (reused)
      report.preconditioner.setup_seconds = report.preconditioner.smoother_check_seconds = 0;
    if (reuse != PreconditionerReuse::none)
      line.add("preconditioner_reused", reused);
    if (reuse == PreconditionerReuse::transfers)
      line.add("transfers_reused", kept);
    if (reuse == PreconditionerReuse::none)
      preconditioner_.reset();
    result.linear_iterations.push_back(report.iterations);
    // The run's preconditioner seconds: the set-ups and the one check of the level smoother.
    result.setup_seconds +=
        report.preconditioner.setup_seconds + report.preconditioner.smoother_check_seconds;
    result.solve_seconds += report.solve_seconds;
    report_linear_solve(report, line, console_, comm_);
    if (!report.failure.empty())
      return "the linear solve failed: " + report.failure;
    if (settings_.injected_failures.count(++solves_))
      return "the linear solve failed: failure of solve " + std::to_string(solves_) + " injected (Injected failures)";
    // An inexact solve is used when its true residual is small against the right-hand side, or
    // against the residual this step started from: late in a step b is tiny and a direct solve's
    // round-off can exceed it relative to b (a node coming into contact near convergence), while
    // the update it gives is negligible and Newton corrects it.
    const double error = report.relative_residual * report.rhs_norm;
    if (!report.converged && !(report.relative_residual <= settings_.accepted_linear_residual ||
                               error <= settings_.accepted_linear_residual * step_residual))
      {
        std::ostringstream why;
        why << "the linear solve failed: GMRES stopped after " << report.iterations
            << " iterations at a true relative residual of " << report.relative_residual << " (accepted: "
            << settings_.accepted_linear_residual << ")";
        return why.str();
      }
    return "";
  }

  std::string NewtonSolver::state_cycle(std::uint64_t state, int iteration, double residual, StatesSeen& seen,
                                        std::uint64_t& last)
  {
    if (state == 0)
      return "";
    // A set that comes back with a residual well below the one it had before is the iteration
    // closing in on a solution (the iterate, not only the set, decides the next step under finite
    // deformation); one that comes back without that progress is a cycle.
    std::string failure;
    const auto  earlier = seen.find(state);
    if (state != last && earlier != seen.end() && residual > 0.5 * earlier->second.second)
      failure = "the active set cycles: the set of Newton step " + std::to_string(earlier->second.first) +
                " is back at step " + std::to_string(iteration) + " without reducing the residual";
    seen[state] = {iteration, residual};
    last        = state;
    return failure;
  }

  NewtonResult NewtonSolver::solve(NonlinearProblem& problem, const std::function<void(JsonLinesLog::Line&)>& step_fields,
                                   const std::string& export_prefix)
  {
    const auto               names = problem.field_names();
    NewtonResult             result;
    // largest: each field's largest norm of this step (the relative tolerances' reference);
    // since_update: the largest after the first update and after the last change of the
    // problem's state (active set), the reference of divergence: the first update applies the
    // load increment and an active-set change adds or drops constraints, and either may raise
    // a field from zero to ordinary values.
    std::vector<double>      largest, since_update;
    double                   merit_before = 0, step_length = 1;
    multigrid::RCP<multigrid::MultiVector> dx;
    // The problem's discrete states of this step (signature -> last iteration, its residual).
    StatesSeen                   states_seen;
    std::uint64_t                last_state = 0;
    preconditioner_.reset(); // a kept preconditioner serves one Newton solve (one load/time step)

    // One linearization with its log line started: returns false (result.failure set) if the
    // assembly failed.
    Linearization      lin;
    JsonLinesLog::Line line;
    double             combined = 0;
    auto linearize = [&](int it) {
      line = JsonLinesLog::Line();
      step_fields(line);
      line.add("newton", it);
      dealii::Timer wall;
      try
        {
          dealii::TimerOutput::Scope scope(timer_, "assembly");
          lin = problem.linearize(it);
        }
      catch (const std::domain_error& e)
        {
          // Logged by the caller: the line search may still take a shorter update.
          result.failure = std::string("the assembly failed: ") + e.what();
          return false;
        }
      const double seconds = wall.wall_time();
      const auto&  norms   = lin.residual_norms;
      if (it == 0)
        largest = norms;
      for (std::size_t f = 0; f < norms.size(); ++f)
        largest[f] = std::max({largest[f], norms[f], f < lin.residual_scales.size() ? lin.residual_scales[f] : 0.0});
      combined = 0;
      for (const double n : norms)
        combined += n * n;
      combined = std::sqrt(combined);
      const double first_combined = result.residuals.empty() ? combined : result.residuals.front();
      line.add("residual", combined).add("relative_residual", first_combined > 0 ? combined / first_combined : 0.0);
      for (std::size_t f = 0; f < norms.size(); ++f)
        line.add("residual_" + names[f], norms[f]);
      line.add("assembly_seconds", seconds);
      return true;
    };
    auto print_iterate = [&](int it) {
      console_ << std::setw(6) << "" << std::setw(7) << it << std::scientific << std::setprecision(3) << std::setw(13)
               << combined;
      for (const double n : lin.residual_norms)
        console_ << std::setw(12) << n;
      console_ << std::defaultfloat;
      std::ostringstream columns;
      problem.describe(line, columns);
      console_ << columns.str();
    };

    for (int it = 0;; ++it)
      {
        bool assembled = linearize(it);
        // Backtracking: take half of the last update back while the merit function grew or the
        // update inverted an element. Only where the problem's state (the active set) stayed as
        // it was: a semi-smooth Newton step that changes the active set may raise the residual by
        // orders of magnitude on its way to the solution, and shortening it only stalls the
        // iteration between sets (measured on the collapsing rings: 20 Newton steps without
        // convergence where the full steps converge or reveal a cycle at once).
        const auto reject = [&] {
          return !assembled || (problem.may_converge() && std::isfinite(merit_before) &&
                                !(merit(lin.residual_norms, largest) < merit_before));
        };
        for (int halving = 0; settings_.line_search && it > 0 && halving < settings_.line_search_steps && reject();
             ++halving)
          {
            line.add("line_search_rejected", step_length);
            if (!assembled)
              line.add("rejected_because", result.failure);
            log_.write(line);
            step_length *= 0.5;
            problem.set_update_length(step_length);
            result.failure.clear();
            assembled = linearize(it);
            line.add("step_length", step_length);
          }
        if (!assembled)
          {
            line.add("failure", result.failure);
            log_.write(line);
            return result;
          }
        result.residuals.push_back(combined);
        print_iterate(it);

        // Divergence is judged only where the problem's own state settled (contact: an unchanged
        // active set); a semi-smooth Newton step that changes the active set may raise the
        // residual by orders of magnitude and still converge.
        result.failure = residual_failure(lin.residual_norms, problem.may_converge() ? since_update : std::vector<double>(),
                                          names);
        if (result.failure.empty())
          result.failure = state_cycle(problem.state_signature(), it, combined, states_seen, last_state);
        if (!problem.may_converge())
          since_update.clear(); // the reference starts again from the first iterate after the change
        else if (it >= 1)
          {
            if (since_update.empty())
              since_update = lin.residual_norms;
            for (std::size_t f = 0; f < since_update.size(); ++f)
              since_update[f] = std::max(since_update[f], lin.residual_norms[f]);
          }
        const bool converged     = result.failure.empty() && it > 0 && problem.may_converge() &&
                               fields_converged(lin.residual_norms, largest);
        if (result.failure.empty() && !converged && it == settings_.max_iterations)
          result.failure = "no convergence in " + std::to_string(it) + " Newton steps";
        line.add("converged", converged);
        if (converged || !result.failure.empty())
          {
            if (!result.failure.empty())
              line.add("failure", result.failure);
            console_ << "\n";
            log_.write(line);
            result.converged = converged;
            return result;
          }

        if (settings_.export_systems)
          multigrid::write_block_system(*lin.system, settings_.export_directory + "/" + export_prefix + "-newton" +
                                                         std::to_string(it));
        dx = Xpetra::MultiVectorFactory<multigrid::SC, multigrid::LO, multigrid::GO, multigrid::NO>::Build(
            lin.system->full_map(), 1, true);
        result.failure =
            solve_linear(*lin.system, *dx, result.residuals.front(), line, result,
                         settings_.export_aggregates ? settings_.aggregates_directory + "/" + export_prefix +
                                                           "-newton" + std::to_string(it)
                                                     : "",
                         problem.state_signature());
        if (!result.failure.empty())
          {
            line.add("failure", result.failure);
            log_.write(line);
            return result;
          }
        log_.write(line);
        merit_before = merit(lin.residual_norms, largest);
        step_length  = 1;
        problem.update(*dx);
        ++result.iterations;
      }
  }
} // namespace physics
