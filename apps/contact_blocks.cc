// contact_blocks: frictionless mortar contact of hyperelastic bodies (2D or 3D; two bodies, or
// any number with contact pairs), quasi-static or dynamic, semi-smooth Newton, GMRES with the
// block-AMG presets. Everything is set in a .prm file.
//
//   mpirun -np 2 contact_blocks apps/contact_blocks_2d.prm
//   mpirun -np 2 contact_blocks apps/contact_rings_2d.prm     (24 collapsing rings)
//   contact_blocks --print-parameters      (all parameters with their documentation)
#include "common/app_main.h"
#include "contact/contact_problem.h"
#include "temporary_files.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>

namespace
{
  const char* usage = R"USAGE(usage: contact_blocks [PARAMETER_FILE.prm] [--set "Section/Entry=value"]... [--restart DIR]
       contact_blocks --help | --print-parameters

Frictionless mortar contact of two or more bodies meshed with gmsh (2D plane strain or 3D;
quasi-static or generalized-alpha dynamics; Contact/Contact surface ids and Contact/Pairs for
many bodies),
semi-smooth Newton (active set updated inside the Newton loop), each Newton system solved by GMRES
preconditioned with a preset of the block-AMG module. Writes Directory/run_log.jsonl (one JSON
object per Newton step), Directory/solution.pvd (+ pvtu per load step) and, on request, every
Newton system as a BlockSystem directory for solve_block_system.

  --print-parameters   print every parameter with its default and documentation, then exit
  --set S/E=V          override one parameter after reading the file, e.g.
                       --set "Linear solver/Preset=direct(superlu)"
  --restart DIR        continue a run from its checkpoint DIR (Restart/Interval wrote it; DIR may be
                       OUTPUT/restart, its newest): same parameters and number of MPI ranks
Exit status: 0 converged, 1 Newton did not converge, 2 bad input.
)USAGE";
}

namespace
{
  /// The final slave-node state as CSV (for postprocessing, e.g. the Hertz comparison), written
  /// to a temporary and renamed so that an interrupted run leaves no partial file.
  void write_contact_nodes(const physics::contact::ContactRunSummary& summary, const std::string& csv)
  {
    const std::string tmp = multigrid::unique_temporary_name(csv);
    {
      std::ofstream out(tmp);
      out << "x,y,z,contact_pressure,weight,active,tangential_traction,slip\n" << std::setprecision(12);
      for (std::size_t j = 0; j < summary.active.size(); ++j)
        out << summary.slave_positions[j][0] << "," << summary.slave_positions[j][1] << ","
            << summary.slave_positions[j][2] << "," << summary.normal_pressure[j] << "," << summary.weight[j]
            << "," << (summary.active[j] ? 1 : 0) << "," << summary.tangential[j] << ","
            << (summary.slip[j] ? 1 : 0) << "\n";
    }
    std::filesystem::rename(tmp, csv);
  }

  void print_contact_state(const physics::contact::ContactRunSummary& summary)
  {
    double p_min = 0, p_max = 0, force = 0, tangential_force = 0;
    int    n_active = 0, n_slip = 0;
    for (std::size_t j = 0; j < summary.active.size(); ++j)
      if (summary.active[j])
        {
          const double pn = summary.normal_pressure[j];
          tangential_force += summary.weight[j] * summary.tangential[j];
          n_slip += summary.slip[j];
          p_min = n_active == 0 ? pn : std::min(p_min, pn);
          p_max = n_active == 0 ? pn : std::max(p_max, pn);
          force += summary.weight[j] * pn;
          ++n_active;
        }
    std::cout << "Contact: " << n_active << " active slave nodes, pressure min " << p_min << " max " << p_max
              << ", total normal force " << force << "\n";
    if (tangential_force > 0) // friction
      std::cout << "Friction: " << n_slip << " of " << n_active
                << " active nodes slip, sum of weighted |lambda_tau| " << tangential_force << "\n";
    std::cout << std::setprecision(16) << "Displacement norms: l2 " << summary.displacement_l2 << ", max "
              << summary.max_displacement << "\n"
              << std::defaultfloat << std::setprecision(6)
              << "Largest penetration of the converged steps (max -g~_j / w_j): " << summary.max_penetration << "\n";
  }
} // namespace

int main(int argc, char** argv)
{
  using physics::contact::ContactParameters;
  return physics::app_main<ContactParameters>(argc, argv, "contact_blocks", usage,
                                              [](const ContactParameters& p, bool root) {
    const auto summary = physics::contact::run_contact(p, MPI_COMM_WORLD);
    if (root)
      {
        std::cout << summary.summary_line(p.dynamic() ? "time" : "load") << "\n";
        write_contact_nodes(summary, p.output_directory + "/contact_nodes.csv");
        print_contact_state(summary);
      }
    return summary.converged ? 0 : 1;
  });
}
