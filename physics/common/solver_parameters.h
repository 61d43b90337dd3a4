// The Newton, step-control and linear-solver settings every app's parameter file shares
// (sections "Newton", "Step control", "Restart" and "Linear solver"), read once here; each app only chooses
// its defaults and names its residual fields.
#pragma once

#include "common/run_output.h"
#include "common/step_driver.h"

#include "krylov_solver.h"
#include "presets.h"

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/parameter_handler.h>

#include <map>
#include <set>
#include <string>
#include <vector>

namespace physics
{
  struct SolverParameters
  {
    SolverParameters() = default;
    /// An app's defaults of the most used values.
    SolverParameters(double newton_relative, double newton_absolute, int newton_iterations, std::string preset_name,
                     std::vector<std::string> preset_overrides, double linear_relative, int linear_iterations,
                     int gmres_restart)
        : newton_relative_tolerance(newton_relative)
        , newton_absolute_tolerance(newton_absolute)
        , newton_max_iterations(newton_iterations)
        , preset(std::move(preset_name))
        , overrides(std::move(preset_overrides))
        , linear_tolerance(linear_relative)
        , linear_max_iterations(linear_iterations)
        , restart(gmres_restart)
    {
    }

    // Newton
    double newton_relative_tolerance = 1e-8, newton_absolute_tolerance = 1e-12;
    int    newton_max_iterations     = 30;
    // Linear solver (GMRES with a preset of multigrid/presets)
    std::string              preset = "emin(cheapsimple)";
    std::vector<std::string> overrides;
    double                   linear_tolerance      = 1e-8;
    int                      linear_max_iterations = 500, restart = 100;
    double                   accepted_linear_residual = 1e-3;
    PreconditionerReuse      reuse_preconditioner     = PreconditionerReuse::none;
    std::set<int>            injected_failures; ///< testing: solves reported as failed
    // Newton, continued: divergence, line search, per-field tolerances (field name -> values set
    // in the file; fields not listed use the two tolerances above)
    double                                divergence_factor = 1e6;
    bool                                  line_search       = false;
    int                                   line_search_steps = 4;
    std::map<std::string, FieldTolerance> field_tolerances;
    // Step control
    int    max_step_cuts = 5, growth_after = 2;
    double minimum_step_fraction = 1e-3;
    bool   return_free_memory    = true;
    // Restart
    int         checkpoint_interval = 0;
    std::string resume_from;

    /// Declares the sections "Newton" (with a subsection per residual field in `fields`),
    /// "Step control" and "Linear solver" with this object's values as the defaults.
    void declare(dealii::ParameterHandler& prm, const std::vector<std::string>& fields) const;
    /// Reads and checks them; throws std::invalid_argument "parameter 'X' ...".
    void parse(dealii::ParameterHandler& prm, const std::vector<std::string>& fields);

    /// The preset with the overrides applied (throws multigrid::InputError for unknown ones).
    multigrid::Preset           load_preset() const;
    multigrid::SolveOptions     solve_options() const;
    /// Newton settings for a problem with these residual fields.
    NewtonSettings newton_settings(const std::vector<std::string>& fields) const;
    /// Step settings for steps of nominal length `step` up to `end_time`, checkpoints under
    /// `output_directory`/restart.
    StepSettings step_settings(double end_time, double step, const std::string& output_directory) const;
  };

  /// A Newton step's linear solve in the run log (iterations, convergence, true relative
  /// residual, setup/solve seconds, size, the preconditioner's operator complexity, and the
  /// largest peak resident memory of any rank so far, MB) and as the console columns
  /// "GMRES setup[s] solve[s]". Collective over `comm`.
  void report_linear_solve(const multigrid::SolveReport& report, JsonLinesLog::Line& line,
                           dealii::ConditionalOStream& console, MPI_Comm comm);
} // namespace physics
