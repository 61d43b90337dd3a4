// beam_solid: fibres (torsion-free Kirchhoff-Love beams) embedded in a Saint Venant-Kirchhoff
// block, tied along their centrelines with a penalty (mortar-type or Gauss-point-to-segment
// coupling), Newton + GMRES with the block presets. Everything is set in a .prm file.
//
//   mpirun -np 2 beam_solid apps/beam_solid_cube.prm
//   beam_solid --print-parameters      (all parameters with their documentation)
#include "beam_solid/beam_solid_problem.h"
#include "common/app_main.h"

#include <iomanip>
#include <iostream>

namespace
{
  const char* usage = R"USAGE(usage: beam_solid [PARAMETER_FILE.prm] [--set "Section/Entry=value"]... [--restart DIR]
       beam_solid --help | --print-parameters

Beam/solid meshtying with penalty coupling (seed 001): straight fibres embedded in a box of Saint
Venant-Kirchhoff material, clamped at x = 0 and pulled by a dead traction at x = a; Newton's method
with the 2 x 2 block system [beam | solid] solved by GMRES with a block preconditioner preset.
Writes Directory/run_log.jsonl (one JSON object per Newton step), Directory/solid.pvd and
Directory/beams.pvd (ParaView), and on request every Newton system for solve_block_system.

  --print-parameters   print every parameter with its default and documentation, then exit
  --set S/E=V          override one parameter after reading the file
  --restart DIR        continue a run from its checkpoint DIR (Restart/Interval wrote it; DIR may be
                       OUTPUT/restart, its newest): same parameters and number of MPI ranks
Exit status: 0 converged, 1 Newton did not converge, 2 bad input.
)USAGE";
}

int main(int argc, char** argv)
{
  using physics::beam_solid::BeamSolidParameters;
  return physics::app_main<BeamSolidParameters>(argc, argv, "beam_solid", usage,
                                                [](const BeamSolidParameters& p, bool root) {
    const auto summary = physics::beam_solid::run_beam_solid(p, MPI_COMM_WORLD);
    if (root)
      std::cout << summary.summary_line("load") << "\n"
                << "Mean x displacement of the loaded face " << summary.mean_end_displacement
                << ", largest beam/solid gap " << summary.max_gap << "\n"
                << std::setprecision(16) << "Displacement norms: solid " << summary.solid_displacement_l2 << ", beam "
                << summary.beam_displacement_l2 << "\n";
    return summary.converged ? 0 : 1;
  });
}
