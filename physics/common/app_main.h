// The main() every app of the project shares:
//
//   MPI and Tpetra start-up -> the app's parameters declared -> the command line read
//   (common/app_parameters.h) -> the parameters parsed and checked -> the run directory with
//   used_parameters.prm -> the app's run -> exit status (0 converged, 1 not, 2 bad input,
//   3 other errors, with one clean line on stderr; run_app()).
//
// An app supplies its usage text, its Parameters type (static declare(prm), parse(prm), and an
// `output_directory`, i.e. OutputParameters) and what it does with the parsed parameters:
//
//   int main(int argc, char** argv)
//   {
//     return physics::app_main<MyParameters>(argc, argv, "my_app", usage,
//                                            [](const MyParameters& p, bool root) { ... return 0; });
//   }
#pragma once

#include "common/app_parameters.h"

#include <deal.II/base/parameter_handler.h>

#include <functional>
#include <string>

namespace physics
{
  /// The untyped part: MPI/Tpetra, declare, read the command line, then `run(prm, root)` inside
  /// run_app() (root: rank 0 of MPI_COMM_WORLD).
  int app_main(int argc, char** argv, const std::string& app, const char* usage,
               const std::function<void(dealii::ParameterHandler&)>&    declare,
               const std::function<int(dealii::ParameterHandler&, bool)>& run);

  /// Creates the run's output directory (collective) and writes every parameter it uses there,
  /// defaults included (used_parameters.prm).
  void open_run_directory(const dealii::ParameterHandler& prm, const std::string& directory);

  template <class Parameters, class Run>
  int app_main(int argc, char** argv, const std::string& app, const char* usage, const Run& run)
  {
    return app_main(argc, argv, app, usage, &Parameters::declare, [&](dealii::ParameterHandler& prm, bool root) {
      Parameters p;
      p.parse(prm);
      open_run_directory(prm, p.output_directory);
      return run(static_cast<const Parameters&>(p), root);
    });
  }
} // namespace physics
