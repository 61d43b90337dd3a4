// The output directory of a run and what every run leaves in it besides its results: the
// parameters it really used (used_parameters.prm, every entry, defaults included, so that a run
// can be repeated from its output alone) and the summary of its timers in the run log.
#pragma once

#include "common/run_output.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>

#include <mpi.h>

#include <string>

namespace physics
{
  /// Creates `directory` (rank 0; collective) and checks that files can be written there.
  /// Throws std::invalid_argument "parameter 'Directory' (Output): cannot create 'D' (reason)".
  void prepare_output_directory(const std::string& directory, MPI_Comm comm);

  /// Writes every parameter of `prm` as a .prm file to directory/used_parameters.prm (rank 0,
  /// atomically): the run's input as read, with the defaults of everything it did not set.
  void write_used_parameters(const dealii::ParameterHandler& prm, const std::string& directory, MPI_Comm comm);

  /// One log line {"event": "timers", "<section>_seconds": wall time, ..., "peak_memory_mb_max",
  /// "peak_memory_mb_mean"} with each section's largest wall time over the ranks and the peak
  /// resident memory per rank (largest, mean; collective), and the same on the console.
  void log_timer_summary(const dealii::TimerOutput& timer, JsonLinesLog& log, std::ostream& console, bool root,
                         MPI_Comm comm);

} // namespace physics
