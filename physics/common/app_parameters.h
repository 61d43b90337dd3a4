// The command line every app of the project shares:
//   APP [PARAMETER_FILE.prm] [--set "Section/Entry=value"]... [--restart DIR] | --help | --print-parameters
// (--restart DIR is --set "Restart/Resume from=DIR").
// The parameter file is read into a ParameterHandler whose entries the app has declared.
#pragma once

#include <deal.II/base/parameter_handler.h>

#include <functional>
#include <string>

namespace physics
{
  /// Reads argv into `prm`. Returns false when the app should stop with exit status 0 (--help
  /// printed `usage`, or --print-parameters printed every parameter; on rank 0 only, `root`).
  /// Throws std::invalid_argument with a one-line message for an unknown argument, a missing
  /// parameter file, and for every line of it or --set that names an undeclared section or entry
  /// ("FILE:LINE: unknown entry 'X' in section 'S' (did you mean 'Y'?)"), gives a value outside
  /// the entry's pattern (said in words) or is not prm syntax. A value of an input-file entry
  /// (Patterns::FileName::input) written in the file is made relative to the file's directory;
  /// --set values are taken as given (relative to the working directory).
  bool read_command_line(int argc, char** argv, const std::string& usage, dealii::ParameterHandler& prm, bool root);

  /// Runs an app's `body` (its exit status: 0 converged, 1 not) and turns what it throws into the
  /// project's exit statuses, with one line "APP: message" on stderr (rank 0 only): 2 for bad
  /// input (std::invalid_argument, multigrid::InputError, a parameter Teuchos/MueLu refuses), 3 for
  /// any other error; the message is made one clean line (no deal.II dump, no Teuchos throw site).
  int run_app(const std::string& app, bool root, const std::function<int()>& body);
} // namespace physics
