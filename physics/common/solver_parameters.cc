#include "common/solver_parameters.h"

#include "common/parameter_checks.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <iomanip>
#include <optional>
#include <sstream>

namespace physics
{
  using dealii::Patterns::Anything;
  using dealii::Patterns::Bool;
  using dealii::Patterns::Double;
  using dealii::Patterns::Integer;
  using dealii::Patterns::Selection;

  namespace
  {
    std::string text(double v) // shortest form: "1e-12", not 9.9999999999999998e-13
    {
      std::ostringstream out;
      out << v;
      return out.str();
    }

    /// A per-field tolerance entry: empty (use the section's value) or a number in range.
    std::optional<double> optional_tolerance(const std::string& value, const std::string& name, bool relative)
    {
      if (value.empty())
        return std::nullopt;
      const double v = parameters::numbers(value, name, 1)[0];
      if (relative)
        return parameters::tolerance(v, "'" + name + "'");
      if (!(v >= 0))
        throw std::invalid_argument("parameter '" + name + "': expected a value >= 0, got " + value);
      return v;
    }

    /// 'Reuse preconditioner': false / true (the whole preconditioner) / transfers.
    std::string reuse_name(PreconditionerReuse reuse)
    {
      return reuse == PreconditionerReuse::whole       ? "true"
             : reuse == PreconditionerReuse::transfers ? "transfers"
                                                       : "false";
    }

    PreconditionerReuse reuse_from_name(const std::string& name)
    {
      return name == "true"        ? PreconditionerReuse::whole
             : name == "transfers" ? PreconditionerReuse::transfers
                                   : PreconditionerReuse::none;
    }
  } // namespace

  void SolverParameters::declare(dealii::ParameterHandler& prm, const std::vector<std::string>& fields) const
  {
    prm.enter_subsection("Newton");
    prm.declare_entry("Relative tolerance", text(newton_relative_tolerance), Double(),
                      "Each residual field converges when ||r_f|| <= this x the largest ||r_f|| of the step's "
                      "iterates (0 < tol < 1), unless its subsection below sets its own.");
    prm.declare_entry("Absolute tolerance", text(newton_absolute_tolerance), Double(),
                      "... or when ||r_f|| <= this (>= 0), unless its subsection below sets its own.");
    prm.declare_entry("Maximum iterations", text(newton_max_iterations), Integer(1, 1000),
                      "Newton steps per load/time step; more is a failed step (cut, see Step control).");
    prm.declare_entry("Divergence factor", text(divergence_factor), Double(),
                      "A field whose residual grows beyond this factor times max(its largest norm since the first "
                      "update, absolute / relative tolerance) has diverged: the step fails and is cut (> 1).");
    prm.declare_entry("Line search", line_search ? "true" : "false", Bool(),
                      "Backtracking: halve the update while it inverts an element or, where the update left "
                      "the problem's discrete state (contact: the active set) unchanged, while the scaled merit "
                      "function sum_f (||r_f|| / s_f)^2 does not decrease (s_f: the field's largest norm of the "
                      "step).");
    prm.declare_entry("Line search steps", text(line_search_steps), Integer(1, 30),
                      "Halvings of one update at most (the last trial is kept).");
    for (const auto& field : fields)
      {
        prm.enter_subsection(field);
        prm.declare_entry("Relative tolerance", "", Anything(),
                          "Relative tolerance of the '" + field + "' residual (empty: the section's).");
        prm.declare_entry("Absolute tolerance", "", Anything(),
                          "Absolute tolerance of the '" + field + "' residual (empty: the section's).");
        prm.leave_subsection();
      }
    prm.leave_subsection();

    prm.enter_subsection("Step control");
    prm.declare_entry("Maximum step cuts", text(max_step_cuts), Integer(0, 60),
                      "A failed load/time step (Newton diverged or ran out of iterations, a failed linear solve, "
                      "an inverted element, a non-finite residual) is retried with half the step, at most this "
                      "many times in a row; 0: a failure stops the run.");
    prm.declare_entry("Minimum step fraction", text(minimum_step_fraction), Double(),
                      "No cut below this fraction of the nominal step (0 < f <= 1).");
    prm.declare_entry("Growth after", text(growth_after), Integer(0, 1000),
                      "After this many converged steps in a row a cut step is doubled again, up to the nominal "
                      "step (0: never).");
    prm.declare_entry(
        "Return free memory", return_free_memory ? "true" : "false", Bool(),
        "After each step's Newton solve, give the heap's free pages back to the system (glibc's "
        "malloc_trim; elsewhere nothing happens), so that the resident memory of a rank does not "
        "creep up over the steps with pages freed by the last assemblies and hierarchies. It keeps "
        "the peak memory per rank lower in long runs but costs time where pages are faulted in "
        "again: measured on a virtual machine, 6-18 % of the rings example's wall time for 3-10 MB. "
        "false: leave them to the allocator.");
    prm.leave_subsection();

    prm.enter_subsection("Restart");
    prm.declare_entry("Interval", text(checkpoint_interval), Integer(0, 1000000000),
                      "Every this many converged steps the run writes a checkpoint to OUTPUT/restart/step_NNNNNN "
                      "(the newest named in OUTPUT/restart/latest; older ones are removed). 0: none.");
    prm.declare_entry("Resume from", "", Anything(),
                      "A checkpoint directory, or a restart/ folder (its newest checkpoint), to continue a run "
                      "from, on the same number of MPI ranks with the same parameters (the command line's "
                      "--restart DIR sets it). Empty: start at the beginning.");
    prm.leave_subsection();

    prm.enter_subsection("Linear solver");
    prm.declare_entry("Preset", preset, Anything(),
                      "Preconditioner preset of multigrid/presets (solve_block_system --list-presets).");
    prm.declare_entry("Overrides", "", Anything(),
                      "Semicolon-separated PATH=VALUE changes of the preset, e.g. "
                      "'template parameters/MIN_AGG_SIZE=6'.");
    prm.declare_entry("Tolerance", text(linear_tolerance), Double(), "GMRES relative residual (0 < tol < 1).");
    prm.declare_entry("Maximum iterations", text(linear_max_iterations), Integer(1, 100000), "GMRES iterations.");
    prm.declare_entry("Restart", text(restart), Integer(1, 10000), "GMRES restart length.");
    prm.declare_entry("Accepted residual", text(accepted_linear_residual), Double(),
                      "A GMRES solve that stops unconverged is still used (inexact Newton) when its true "
                      "residual is at most this times ||b|| or this times the step's first Newton residual; "
                      "above both (or on a breakdown) the step fails and is cut (0 < value < 1). The default "
                      "tolerates an inexact solve (SuperLU without equilibration stalls near 1e-6 on contact "
                      "systems) but not one that barely reduced the residual.");
    prm.declare_entry(
        "Reuse preconditioner", reuse_name(reuse_preconditioner), Selection("false|true|transfers"),
        "What the following Newton steps of the same load/time step keep of a Newton step's "
        "preconditioner while the problem's discrete state (contact: the active set and "
        "stick/slip) is the one it was built for. false: nothing, every Newton step sets up "
        "a new one; true: the whole preconditioner (GMRES solves the new matrix with the old "
        "hierarchy); transfers: the hierarchy's aggregates and prolongators, set up again on "
        "the new matrix without the aggregation (coarse operators, smoothers and coarse solver "
        "are new; presets with a MueLu hierarchy: the blocked ones, cheapsimple's inner AMGs (its "
        "Schur complement formed anew) and amg; direct presets set up a new one). A "
        "solve with a kept preconditioner that does not converge is repeated with a fresh one. "
        "Saves set-up time where Newton only polishes a settled active set.");
    prm.declare_entry("Injected failures", "", Anything(),
                      "For testing the failure handling: comma-separated numbers of linear solves (counted from 1 "
                      "over the run) that are reported as failed after they ran. Empty: none.");
    prm.leave_subsection();
  }

  void SolverParameters::parse(dealii::ParameterHandler& prm, const std::vector<std::string>& fields)
  {
    prm.enter_subsection("Newton");
    newton_relative_tolerance =
        parameters::tolerance(prm.get_double("Relative tolerance"), "'Relative tolerance' (Newton)");
    newton_absolute_tolerance = prm.get_double("Absolute tolerance");
    if (!(newton_absolute_tolerance >= 0))
      throw std::invalid_argument("parameter 'Absolute tolerance' (Newton): expected a value >= 0");
    newton_max_iterations = prm.get_integer("Maximum iterations");
    divergence_factor     = prm.get_double("Divergence factor");
    if (!(divergence_factor > 1))
      throw std::invalid_argument("parameter 'Divergence factor': expected a value > 1, got " + text(divergence_factor));
    line_search       = prm.get_bool("Line search");
    line_search_steps = prm.get_integer("Line search steps");
    field_tolerances.clear();
    for (const auto& field : fields)
      {
        prm.enter_subsection(field);
        const auto relative = optional_tolerance(prm.get("Relative tolerance"), "Newton/" + field + "/Relative tolerance", true);
        const auto absolute = optional_tolerance(prm.get("Absolute tolerance"), "Newton/" + field + "/Absolute tolerance", false);
        prm.leave_subsection();
        if (relative || absolute)
          field_tolerances[field] = {absolute.value_or(newton_absolute_tolerance), relative.value_or(newton_relative_tolerance)};
      }
    prm.leave_subsection();

    prm.enter_subsection("Step control");
    max_step_cuts         = prm.get_integer("Maximum step cuts");
    minimum_step_fraction = prm.get_double("Minimum step fraction");
    if (!(minimum_step_fraction > 0 && minimum_step_fraction <= 1))
      throw std::invalid_argument("parameter 'Minimum step fraction': expected 0 < f <= 1, got " +
                                  text(minimum_step_fraction));
    growth_after       = prm.get_integer("Growth after");
    return_free_memory = prm.get_bool("Return free memory");
    prm.leave_subsection();

    prm.enter_subsection("Restart");
    checkpoint_interval = prm.get_integer("Interval");
    resume_from         = prm.get("Resume from");
    prm.leave_subsection();

    prm.enter_subsection("Linear solver");
    preset                = prm.get("Preset");
    overrides             = dealii::Utilities::split_string_list(prm.get("Overrides"), ';');
    linear_tolerance      = parameters::tolerance(prm.get_double("Tolerance"), "'Tolerance' (Linear solver)");
    linear_max_iterations = prm.get_integer("Maximum iterations");
    restart               = prm.get_integer("Restart");
    accepted_linear_residual =
        parameters::tolerance(prm.get_double("Accepted residual"), "'Accepted residual' (Linear solver)");
    reuse_preconditioner = reuse_from_name(prm.get("Reuse preconditioner"));
    injected_failures.clear();
    for (const double n : parameters::numbers(prm.get("Injected failures"), "Injected failures"))
      {
        if (!(n >= 1) || n != static_cast<int>(n))
          throw std::invalid_argument("parameter 'Injected failures': expected solve numbers >= 1, got " + text(n));
        injected_failures.insert(static_cast<int>(n));
      }
    prm.leave_subsection();
  }

  NewtonSettings SolverParameters::newton_settings(const std::vector<std::string>& fields) const
  {
    NewtonSettings s;
    s.max_iterations           = newton_max_iterations;
    s.divergence_factor        = divergence_factor;
    s.line_search              = line_search;
    s.line_search_steps        = line_search_steps;
    s.accepted_linear_residual = accepted_linear_residual;
    s.reuse_preconditioner     = reuse_preconditioner;
    s.injected_failures        = injected_failures;
    for (const auto& field : fields)
      {
        const auto it = field_tolerances.find(field);
        s.tolerances.push_back(it != field_tolerances.end()
                                   ? it->second
                                   : FieldTolerance{newton_absolute_tolerance, newton_relative_tolerance});
      }
    return s;
  }

  StepSettings SolverParameters::step_settings(double end_time, double step, const std::string& output_directory) const
  {
    StepSettings s;
    s.checkpoint_interval = checkpoint_interval;
    s.checkpoint_root     = output_directory + "/restart";
    s.resume_from         = resume_from;
    s.end_time     = end_time;
    s.step         = step;
    s.minimum_step = minimum_step_fraction * step;
    s.max_cuts     = max_step_cuts;
    s.growth_after = growth_after;
    s.return_free_memory  = return_free_memory;
    return s;
  }

  multigrid::Preset SolverParameters::load_preset() const
  {
    multigrid::Preset p = multigrid::load_preset(preset);
    multigrid::apply_overrides(p, overrides);
    return p;
  }

  void report_linear_solve(const multigrid::SolveReport& report, JsonLinesLog::Line& line,
                           dealii::ConditionalOStream& console, MPI_Comm comm)
  {
    dealii::Utilities::System::MemoryStats memory;
    dealii::Utilities::System::get_memory_stats(memory); // VmHWM: peak resident set, kB
    const double peak_mb = dealii::Utilities::MPI::max(memory.VmHWM / 1024.0, comm);
    line.add("linear_iterations", report.iterations).add("linear_converged", report.converged)
        .add("linear_relative_residual", report.relative_residual)
        .add("setup_seconds", report.preconditioner.setup_seconds).add("solve_seconds", report.solve_seconds)
        .add("global_size", static_cast<long long>(report.global_size))
        .add("operator_complexity", report.preconditioner.operator_complexity).add("peak_memory_mb", peak_mb);
    if (report.preconditioner.smoother_check_seconds > 0)
      line.add("smoother_check_seconds", report.preconditioner.smoother_check_seconds);
    // The AMG levels: rows, and (blocked hierarchies) on how many ranks each lives, which
    // coarse-level rebalancing ("repartition/enable") changes.
    std::vector<long long> rows, ranks;
    for (const auto& level : report.preconditioner.levels)
      {
        rows.push_back(level.rows);
        ranks.push_back(level.ranks);
      }
    if (!rows.empty())
      line.add("level_rows", rows).add("level_ranks", ranks);
    console << std::setw(7) << report.iterations << std::fixed << std::setprecision(2) << std::setw(9)
            << report.preconditioner.setup_seconds << std::setw(9) << report.solve_seconds << std::defaultfloat
            << (report.converged ? "" : "  (GMRES not converged)") << "\n";
  }

  multigrid::SolveOptions SolverParameters::solve_options() const
  {
    multigrid::SolveOptions options;
    options.tolerance      = linear_tolerance;
    options.max_iterations = linear_max_iterations;
    options.restart        = restart;
    return options;
  }
} // namespace physics
