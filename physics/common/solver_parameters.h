// The Newton and linear-solver settings every app's parameter file shares (sections "Newton" and
// "Linear solver"), read once here; each app only chooses its defaults.
#pragma once

#include "common/run_output.h"

#include "krylov_solver.h"
#include "presets.h"

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/parameter_handler.h>

#include <string>
#include <vector>

namespace physics
{
  struct SolverParameters
  {
    // Newton
    double newton_relative_tolerance = 1e-8, newton_absolute_tolerance = 1e-12;
    int    newton_max_iterations     = 30;
    // Linear solver (GMRES with a preset of multigrid/presets)
    std::string              preset = "emin(cheapsimple)";
    std::vector<std::string> overrides;
    double                   linear_tolerance      = 1e-8;
    int                      linear_max_iterations = 500, restart = 100;

    /// Declares the two sections with this object's values as the defaults.
    void declare(dealii::ParameterHandler& prm) const;
    /// Reads and checks them; throws std::invalid_argument "parameter 'X' ...".
    void parse(dealii::ParameterHandler& prm);

    /// The preset with the overrides applied (throws multigrid::InputError for unknown ones).
    multigrid::Preset           load_preset() const;
    multigrid::SolveOptions     solve_options() const;
  };

  /// A Newton step's linear solve in the run log (iterations, convergence, true relative
  /// residual, setup/solve seconds, size, the preconditioner's operator complexity, and the
  /// largest peak resident memory of any rank so far, MB) and as the console columns
  /// "GMRES setup[s] solve[s]". Collective over `comm`.
  void report_linear_solve(const multigrid::SolveReport& report, JsonLinesLog::Line& line,
                           dealii::ConditionalOStream& console, MPI_Comm comm);
} // namespace physics
