// GMRES (Belos, right preconditioning, restarted) on a BlockSystem with a BlockPreconditioner, and
// the solve report: iterations, relative residual history, true residuals per block, setup/solve
// seconds, hierarchy description. Reports are written as JSON (atomically) and as a table.
#pragma once

#include "block_preconditioner.h"
#include "block_system.h"

#include <ostream>
#include <string>
#include <vector>

namespace multigrid
{
  struct SolveOptions
  {
    double tolerance      = 1e-8; ///< relative residual ||b - A x|| / ||b|| (x0 = 0)
    int    max_iterations = 500;
    int    restart        = 100;
    /// Apply the tolerance to every block's residual separately (||r_k|| / ||b_k||), as in the
    /// peer code's runs, in addition to the whole residual.
    bool per_block = false;
  };

  struct SolveReport
  {
    bool                     converged  = false;
    std::string              failure; ///< why the solve broke down (empty: it ran; see converged)
    int                      iterations = 0;
    std::vector<double>      residual_history;      ///< relative (implicit) residual per iteration
    double                   relative_residual = 0; ///< true ||b - A x|| / ||b||
    double                   rhs_norm          = 0; ///< ||b||
    std::vector<std::string> block_names;
    std::vector<double>      block_relative_residuals; ///< ||r_k|| / ||b_k|| (absolute if b_k = 0)
    double                   solve_seconds = 0;
    PreconditionerInfo       preconditioner;
    long long                global_size = 0;
    int                      ranks       = 1;
    /// Peak resident memory of the process (VmHWM) after the solve, largest and mean over the
    /// ranks, in MB: the system, the hierarchy and the Krylov space together (0 where /proc is
    /// not available).
    double       peak_memory_mb_max  = 0;
    double       peak_memory_mb_mean = 0;
    SolveOptions options;
  };

  /// Solves A x = b; x (on the system's full map) is overwritten. Never throws for
  /// non-convergence or a breakdown: the report says so (a breakdown leaves x = NaN, so that a
  /// caller ignoring the report cannot mistake it for a solution).
  SolveReport solve(const BlockSystem& system, const BlockPreconditioner& preconditioner, MultiVector& x,
                    const SolveOptions& options);

  /// Human-readable table (rank 0 prints it).
  void print_report(std::ostream& out, const SolveReport& report);

  /// One JSON object; written to a temporary of its own beside FILE and renamed, so readers never
  /// see a partial file.
  std::string to_json(const SolveReport& report);
  void        write_json_atomically(const std::string& file, const std::string& json);
} // namespace multigrid
