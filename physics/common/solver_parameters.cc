#include "common/solver_parameters.h"

#include "common/parameter_checks.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <iomanip>
#include <sstream>

namespace physics
{
  using dealii::Patterns::Anything;
  using dealii::Patterns::Double;
  using dealii::Patterns::Integer;

  void SolverParameters::declare(dealii::ParameterHandler& prm) const
  {
    const auto text = [](auto v) { // shortest form: "1e-12", not 9.9999999999999998e-13
      std::ostringstream out;
      out << v;
      return out.str();
    };
    prm.enter_subsection("Newton");
    prm.declare_entry("Relative tolerance", text(newton_relative_tolerance), Double(),
                      "||r|| / ||r_0|| per load step (0 < tol < 1).");
    prm.declare_entry("Absolute tolerance", text(newton_absolute_tolerance), Double(),
                      "||r|| below this also counts as converged (>= 0).");
    prm.declare_entry("Maximum iterations", text(newton_max_iterations), Integer(1, 1000), "Newton steps per load step.");
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
    prm.leave_subsection();
  }

  void SolverParameters::parse(dealii::ParameterHandler& prm)
  {
    prm.enter_subsection("Newton");
    newton_relative_tolerance =
        parameters::tolerance(prm.get_double("Relative tolerance"), "'Relative tolerance' (Newton)");
    newton_absolute_tolerance = prm.get_double("Absolute tolerance");
    newton_max_iterations     = prm.get_integer("Maximum iterations");
    prm.leave_subsection();

    prm.enter_subsection("Linear solver");
    preset                = prm.get("Preset");
    overrides             = dealii::Utilities::split_string_list(prm.get("Overrides"), ';');
    linear_tolerance      = parameters::tolerance(prm.get_double("Tolerance"), "'Tolerance' (Linear solver)");
    linear_max_iterations = prm.get_integer("Maximum iterations");
    restart               = prm.get_integer("Restart");
    prm.leave_subsection();
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
