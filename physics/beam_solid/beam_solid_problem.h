// Beam/solid meshtying with penalty coupling (seed 001, BENCHMARKS.md section 2), quasi-static:
// a Saint Venant-Kirchhoff block (common layer) with embedded straight fibres (torsion-free
// Kirchhoff-Love beams) tied along their centrelines (beam_solid_coupling.h), Newton's method,
// each linear system the seeds' 2 x 2 block system
//   [ K_B + eps D^T k^-1 D    -eps D^T k^-1 M      ] [dd_B]     [r_B]
//   [ -eps M^T k^-1 D         K_S + eps M^T k^-1 M ] [dd_S] = - [r_S]
// solved by GMRES with a preset of multigrid/.
#pragma once

#include "common/parameter_sections.h"
#include "common/solver_parameters.h"
#include "common/step_driver.h"

#include <deal.II/base/parameter_handler.h>

#include <mpi.h>

#include <string>
#include <vector>

namespace physics::beam_solid
{
  /// Material (the solid) and Output come from the common sections.
  struct BeamSolidParameters : MaterialParameters, OutputParameters
  {
    BeamSolidParameters()
        : MaterialParameters{"SaintVenantKirchhoff", 1.0, 0.3} // N/m^2
        , OutputParameters{"output/beam_solid"}
    {
    }
    // Mesh: the solid is the box [0, size] with `cells` elements per edge
    std::vector<double> size{1.0, 1.0, 1.0};
    std::vector<int>    cells{4, 4, 4};
    bool                balance_coupling_cells = true; ///< partition: equal shares of the cells beams cross
    // Fibres: a gmsh beam mesh (msh 2.2 lines, or a .geo meshed in 1D with `refine` =
    // beam_refinement), or else a grid of ny x nz straight fibres along x through the box
    std::string beam_file;
    int         beam_refinement = 1;
    int    fibres_y = 3, fibres_z = 3, elements_per_fibre = 8;
    double fibre_margin = 0.1;  ///< distance of the outer fibres from the box faces (fraction)
    double fibre_tilt   = 0.0;  ///< fibres rise by this (fraction of the height) over their length
    double beam_youngs_modulus = 10.0, fibre_radius = 0.005;
    // Coupling
    std::string coupling = "mortar"; ///< mortar | gpts
    double      penalty  = 10.0;
    int         gauss_points = 6;
    // Loading: clamped face x = 0, dead traction on x = size_x
    std::vector<double> traction{1.0, 0.0, 0.0};
    int                 load_steps = 1;
    // Newton and linear solver
    SolverParameters solver{1e-6, 1e-12, 20, "direct(superlu)", {}, 1e-8, 1000, 200};

    /// The residual fields Newton checks separately (Newton subsections of the same names):
    /// generalized forces on the beam DOFs (positions and tangents), forces on the solid DOFs.
    static std::vector<std::string> residual_fields() { return {"beam", "solid"}; }

    static void declare(dealii::ParameterHandler& prm);
    /// Reads and checks every value; throws std::invalid_argument "parameter 'X': ...".
    void parse(dealii::ParameterHandler& prm);
  };

  struct BeamSolidRunSummary : RunSummary
  {
    long long beam_dofs = 0, solid_dofs = 0;
    std::size_t coupling_points = 0;
    /// Final state: the loaded face's mean x displacement and the largest beam/solid gap.
    double mean_end_displacement = 0, max_gap = 0;
    double solid_displacement_l2 = 0, beam_displacement_l2 = 0; ///< ||d_S||, ||d_B|| (global vector norms)
    /// This rank's beam DOFs (6 per owned node, beam_partition.h), from global DOF beam_first_dof.
    std::vector<double> beam_displacement;
    long long           beam_first_dof = 0;
  };

  BeamSolidRunSummary run_beam_solid(const BeamSolidParameters& parameters, MPI_Comm comm);
} // namespace physics::beam_solid
