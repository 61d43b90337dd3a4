#include "common/app_main.h"

#include "common/run_directory.h"
#include "trilinos_scope.h"

#include <deal.II/base/mpi.h>

namespace physics
{
  int app_main(int argc, char** argv, const std::string& app, const char* usage,
               const std::function<void(dealii::ParameterHandler&)>&    declare,
               const std::function<int(dealii::ParameterHandler&, bool)>& run)
  {
    dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
    multigrid::TrilinosScope                 tpetra(argv);
    const bool               root = dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
    dealii::ParameterHandler prm;
    declare(prm);
    return run_app(app, root, [&]() {
      if (!read_command_line(argc, argv, usage, prm, root))
        return 0;
      return run(prm, root);
    });
  }

  void open_run_directory(const dealii::ParameterHandler& prm, const std::string& directory)
  {
    prepare_output_directory(directory, MPI_COMM_WORLD);
    write_used_parameters(prm, directory, MPI_COMM_WORLD);
  }
} // namespace physics
