// fsi: condensed (monolithic) fluid/solid interaction on matching interface meshes (seed 001,
// FSI.md): incompressible Navier-Stokes in ALE form (Q1/Q1, PSPG/SUPG/grad-div, BDF1/2), Saint
// Venant-Kirchhoff walls (generalized-alpha), a pseudo-elastic mesh; the interface traction
// condensed out, one Newton iteration for all three fields with the full Jacobian (shape
// derivatives included), each linear system a 3-block BlockSystem (structure, fluid, ALE).
// The cases: a 2D channel between two elastic walls (generated) or a gmsh mesh of fluid and
// structure (the 3D pressure-wave tube, the Turek-Hron channel), a pressure pulse or a parabolic
// velocity on the inlet.
//
//   mpirun -np 2 fsi apps/fsi_channel_2d.prm
//   mpirun -np 2 fsi apps/fsi_tube_3d.prm
//   mpirun -np 2 fsi apps/fsi_turek_hron.prm
//   fsi --print-parameters      (all parameters with their documentation)
#include "common/app_main.h"
#include "fsi/condensed_fsi.h"

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace
{
  const char* usage = R"USAGE(usage: fsi [PARAMETER_FILE.prm] [--set "Section/Entry=value"]... [--restart DIR]
       fsi --help | --print-parameters

Condensed fluid/solid interaction (seed 001): incompressible Newtonian fluid (ALE Navier-Stokes,
Q1/Q1 with PSPG/SUPG/grad-div stabilization, BDF1 or BDF2) in a 2D channel between two Saint
Venant-Kirchhoff walls (generated; fsi_channel_2d.prm) or in a gmsh mesh of fluid and structure
(Mesh/Mesh file, 2D or 3D: the pressure-wave tube, fsi_tube_3d.prm; the Turek-Hron channel with
a rigid cylinder and an elastic flag, fsi_turek_hron.prm), structures (generalized-alpha) clamped
on the inlet/outlet planes and rigid walls, a pseudo-elastic ALE mesh, a pressure pulse or a
parabolic velocity on the inlet, no-slip on rigid walls and obstacles. Matching
interface nodes; the interface traction is condensed onto the structure's interface rows;
Newton with the full Jacobian, each system a 3-block BlockSystem [structure | fluid | ALE]
solved with the chosen preset (direct(superlu) by default).
Writes Directory/run_log.jsonl (one JSON object per Newton step; per time step the fluid's mass
balance, event "fluid_balance"), Directory/wall_displacement.csv (per time step the mean outward
wall displacement at every axial station of the interface nodes; postprocess/fsi_wave_speed.py),
with a rigid obstacle or a monitor point Directory/forces.csv (per time step drag, lift and the
monitor point's displacement; event "obstacle_forces" in the log; the wall profile is not written
with an obstacle), Directory/fluid.pvd and Directory/structure.pvd (ParaView), and on request
every Newton system for solve_block_system.

  --print-parameters   print every parameter with its default and documentation, then exit
  --set S/E=V          override one parameter after reading the file
  --restart DIR        continue a run from its checkpoint DIR (Restart/Interval wrote it; DIR may be
                       OUTPUT/restart, its newest): same parameters and number of MPI ranks
Exit status: 0 converged, 1 Newton did not converge, 2 bad input.
)USAGE";
}

int main(int argc, char** argv)
{
  using physics::fsi::FsiParameters;
  return physics::app_main<FsiParameters>(argc, argv, "fsi", usage, [](const FsiParameters& p, bool root) {
    const auto summary = physics::fsi::run_condensed_fsi(p, MPI_COMM_WORLD);
    if (root)
      {
        const auto&        wall    = summary.max_wall_displacement;
        const double       largest = wall.empty() ? 0.0 : *std::max_element(wall.begin(), wall.end());
        std::ostringstream extra;
        extra << "system: structure " << summary.structure_dofs << ", fluid " << summary.fluid_dofs
              << ", ALE " << summary.ale_dofs << " DOFs; largest relative mass imbalance "
              << std::setprecision(3) << summary.max_mass_imbalance << "; largest wall displacement "
              << std::setprecision(12) << largest;
        std::cout << summary.summary_line("time", extra.str()) << "\n"
                  << std::setprecision(16) << "Displacement norms: structure l2 " << summary.structure_l2
                  << ", max " << summary.structure_max << ", ALE l2 " << summary.ale_l2 << ", fluid l2 "
                  << summary.fluid_l2 << "\n";
        if (!summary.obstacle_force.empty())
          std::cout << std::setprecision(8) << "Force on obstacle and structure: drag "
                    << summary.obstacle_force[0] << ", lift " << summary.obstacle_force[1] << "\n";
        if (!summary.monitor_displacement.empty())
          {
            std::cout << std::setprecision(8) << "Monitor point displacement:";
            for (const double u : summary.monitor_displacement)
              std::cout << " " << u;
            std::cout << "\n";
          }
      }
    return summary.converged ? 0 : 1;
  });
}
