// fsi: condensed (monolithic) fluid/solid interaction on matching interface meshes (seed 001,
// FSI.md): incompressible Navier-Stokes in ALE form (Q1/Q1, PSPG/SUPG/grad-div, BDF1), Saint
// Venant-Kirchhoff walls (generalized-alpha), a pseudo-elastic mesh; the interface traction
// condensed out, one Newton iteration for all three fields with the full Jacobian (shape
// derivatives included), each linear system a 3-block BlockSystem (structure, fluid, ALE).
// The case: a 2D channel between two elastic walls, a pressure pulse on the inlet.
//
//   mpirun -np 2 fsi apps/fsi_channel_2d.prm
//   fsi --print-parameters      (all parameters with their documentation)
#include "common/app_parameters.h"
#include "common/run_directory.h"
#include "fsi/condensed_fsi.h"
#include "trilinos_scope.h"

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <iomanip>
#include <iostream>

namespace
{
  const char* usage = R"USAGE(usage: fsi [PARAMETER_FILE.prm] [--set "Section/Entry=value"]...
       fsi --help | --print-parameters

Condensed fluid/solid interaction (seed 001): a 2D channel of incompressible Newtonian fluid
(ALE Navier-Stokes, Q1/Q1 with PSPG/SUPG/grad-div stabilization, BDF1) between two Saint
Venant-Kirchhoff walls (generalized-alpha) clamped at both ends, a pseudo-elastic ALE mesh, a
pressure pulse on the inlet. Matching interface nodes; the interface traction is condensed onto
the structure's interface rows; Newton with the full Jacobian, each system a 3-block BlockSystem
[structure | fluid | ALE] solved with the chosen preset (direct(superlu) by default).
Writes Directory/run_log.jsonl (one JSON object per Newton step), Directory/fluid.pvd and
Directory/structure.pvd (ParaView), and on request every Newton system for solve_block_system.

  --print-parameters   print every parameter with its default and documentation, then exit
  --set S/E=V          override one parameter after reading the file
Exit status: 0 converged, 1 Newton did not converge, 2 bad input.
)USAGE";
}

int main(int argc, char** argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  multigrid::TrilinosScope                 tpetra(argv);
  const bool               root = dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
  dealii::ParameterHandler prm;
  physics::fsi::FsiParameters::declare(prm);
  return physics::run_app("fsi", root, [&]() {
    if (!physics::read_command_line(argc, argv, usage, prm, root))
      return 0;
    physics::fsi::FsiParameters p;
    p.parse(prm);
    physics::prepare_output_directory(p.output_directory, MPI_COMM_WORLD);
    physics::write_used_parameters(prm, p.output_directory, MPI_COMM_WORLD);
    const auto summary = physics::fsi::run_condensed_fsi(p, MPI_COMM_WORLD);
    if (root)
      {
        int total_newton = 0;
        for (int n : summary.newton_iterations)
          total_newton += n;
        const double wall = summary.max_wall_displacement.empty()
                                ? 0.0
                                : *std::max_element(summary.max_wall_displacement.begin(),
                                                    summary.max_wall_displacement.end());
        std::cout << "Summary: " << summary.newton_iterations.size() << " time steps, " << total_newton
                  << " Newton steps ("
                  << (summary.newton_iterations.empty()
                          ? 0.0
                          : double(total_newton) / summary.newton_iterations.size())
                  << " per step); system: structure " << summary.structure_dofs << ", fluid "
                  << summary.fluid_dofs << ", ALE " << summary.ale_dofs << " DOFs; setup "
                  << summary.setup_seconds << " s, solve " << summary.solve_seconds
                  << " s; largest wall displacement " << std::setprecision(12) << wall << "; "
                  << (summary.converged ? "converged" : "NOT converged") << "\n"
                  << std::setprecision(16) << "Displacement norms: structure l2 " << summary.structure_l2
                  << ", max " << summary.structure_max << ", ALE l2 " << summary.ale_l2 << ", fluid l2 "
                  << summary.fluid_l2 << "\n";
      }
    return summary.converged ? 0 : 1;
  });
}
