// Condensed (monolithic) fluid/solid interaction, the seeds' structure-split formulation
// (FSI.md): the structure (Saint Venant-Kirchhoff, generalized-alpha
// from the common layer), the ALE fluid (ale_fluid.h) and the pseudo-elastic mesh
// (ale_mesh_motion.h) in one Newton iteration, the interface traction eliminated:
//
//   kinematic:  u^F_Gamma = d/dt d^S_Gamma through the fluid's time stencil (the grid velocity's;
//               ale_fluid.h): (a0 d^S_{n+1} + a1 d^S_n + a2 d^S_{n-1}) / dt + a3 r_n,  tau = a0 / dt,
//   geometric:  d^G_Gamma = d^S_Gamma,
//   dynamic:    the fluid's interface rows R^F_Gamma (the traction lambda the structure exerts on
//               the fluid, at t_{n+1}: BDF and one-step-theta in rate form are balances at
//               t_{n+1}) act on the structure as -lambda; generalized-alpha evaluates forces at
//               t_{n+1-af}, so the structure interface rows become
//                 R^S_Gamma + (1 - af) R^F_Gamma + af lambda_n,
//               the seeds' (1-a)/(1-b) with b = 0. (The seeds' b = 1 - theta weights the
//               theta-weighted fluid residual, theta R^F_Gamma + (1 - theta) lambda_n in these
//               terms; eliminating lambda_{n+1} from it gives the same rows.)
// On non-matching interface meshes (Coupling/Interface = dual mortar) the fluid's interface
// values are P = D^-1 M times the structure's (u^F_Gamma = tau P d^S_Gamma + ..., d^G_Gamma = P
// d^S_Gamma) and its interface rows reach the structure as P^T R^F_Gamma; matching nodes are the
// special case P = node map (interface_nodes.h).
//
// Unknowns (the seeds' layout): d^S (inner and interface), the fluid DOFs without the interface
// velocities (u_I, p), and the inner ALE DOFs d^G_I. The Newton system
//   [ S_II  S_IG                                    0            0        ] [dd^S_I]
//   [ S_GI  S_GG + (1-af)(tau F_GG + F^G_GG)        (1-af) F_GI  (1-af) F^G_GI ] [dd^S_G]
//   [ 0     tau F_IG + F^G_IG                       F_II         F^G_II   ] [du^F_I]  = -r
//   [ 0     A_IG                                    0            A_II     ] [dd^G_I]
// is handed over as a BlockSystem of three blocks (structure, fluid, ALE). The condensed interface
// velocities keep their places in the fluid block as decoupled placeholder rows (identity, zero
// right-hand side, their increments ignored), so that the fluid block is node-complete: dim + 1
// DOFs per node, near-nullspace the constant velocities and pressure, aggregated node-wise by the
// AMG (with the pressures alone the interface nodes made the block 1 DOF per node, aggregated
// DOF by DOF with one constant). F^G, the shape derivatives, can be dropped (a parameter).
//
// The MPI layout: the fluid and the structure meshes are fully distributed, each partitioned
// on its own (a rank stores its cells and one ghost layer), and every field keeps deal.II's
// distribution of its mesh; the interface nodes are matched from an all-gather of each rank's
// owned interface nodes (interface_nodes.h, O(interface) per rank), the fluid interface rows
// are sent to the owner of the matching structure DOF (common/row_exchange.h), and the
// structure values the owned fluid and ALE interface DOFs need are ghosts of the structure
// vectors.
#pragma once

#include "common/solver_parameters.h"
#include "common/parameter_sections.h"
#include "common/step_driver.h"
#include "fsi/ale_fluid.h"

#include <deal.II/base/parameter_handler.h>

#include <mpi.h>

#include <string>
#include <vector>

namespace physics::fsi
{
  /// The case: the generated 2D channel between two elastic walls (apps/fsi_channel_2d.prm):
  /// fluid in [0, L] x [0, H], walls [0, L] x [-t, 0] and [0, L] x [H, H + t], or a gmsh mesh of
  /// fluid and structure (the 3D tube, apps/fsi_tube_3d.prm; the Turek-Hron channel,
  /// apps/fsi_turek_hron.prm; fsi_meshes.h): structures clamped on the inlet and outlet planes and
  /// on rigid walls and obstacles, a pressure pulse or a parabolic velocity on the inlet, the
  /// outlet traction-free, no-slip on rigid walls and obstacles.
  /// Mesh file, Material (the walls) and Output come from the common sections.
  struct FsiParameters : MeshParameters, MaterialParameters, OutputParameters
  {
    FsiParameters()
        : MeshParameters{""}                                        // empty: the generated channel
        , MaterialParameters{"SaintVenantKirchhoff", 3e6, 0.3, 1.2} // dyn/cm^2, g/cm^3
        , OutputParameters{"output/fsi"}
    {
    }
    int dimension = 2; ///< 3 needs a mesh file
    // The generated channel (matching nodes on the interface)
    double length = 6.0, height = 1.0, wall_thickness = 0.1; // cm
    int    cells_x = 30, cells_fluid_y = 6, cells_wall_y = 1;
    int    cells_wall_x = 0; ///< 0: cells_x (matching interface nodes)
    // Fluid
    double fluid_density = 1.0, fluid_viscosity = 0.03; // g/cm^3, P (CGS)
    bool   tau_with_time_step = true;                   ///< tau_M with its (2/dt)^2 term (FluidModel)
    // Structure: generalized-alpha
    double spectral_radius = 1.0;
    // ALE mesh
    double ale_poisson_ratio = 0.3, ale_stiffening = 1.0;
    // Load and time
    double inlet_pressure = 1.3332e4, pulse_duration = 3e-3, time_step = 1e-4, end_time = 1e-3;
    bool   parabolic_inflow     = false; ///< a parabolic inflow velocity instead of the pressure pulse
    double mean_inflow_velocity = 0.2, inflow_ramp_time = 0;
    std::vector<double> monitor_point; ///< a structure node's reference position (empty: none)
    /// The fluid's (and the grid and interface velocities') time derivative (ale_fluid.h).
    FluidTimeScheme fluid_scheme = FluidTimeScheme::bdf1;
    double          fluid_theta  = 0.5; ///< one-step-theta's theta
    bool   shape_derivatives = true;
    bool   dual_mortar       = false; ///< the interface by dual mortar (non-matching meshes)
    bool   check_jacobian    = false; ///< testing: J v against central differences in step 2
    // Newton and linear solver
    SolverParameters solver{1e-6, 1e-10, 15, "direct(superlu)", {}, 1e-8, 500, 200};

    static std::vector<std::string> residual_fields() { return {"structure", "fluid", "ale"}; }
    static void                     declare(dealii::ParameterHandler& prm);
    /// Reads and checks every value; throws std::invalid_argument "parameter 'X' (Section): ...".
    void parse(dealii::ParameterHandler& prm);
    /// "x, y[, z]" (or blanks between) with `dim` numbers (empty text: none); throws naming 'Monitor point'.
    static std::vector<double> parse_point(const std::string& text, int dim);
  };

  struct FsiRunSummary : RunSummary
  {
    long long structure_dofs = 0, fluid_dofs = 0, ale_dofs = 0; ///< blocks of the Newton system
    /// Per converged step: the largest wall displacement (normal to the wall).
    std::vector<double> max_wall_displacement;
    /// At the end: ||d^S||_2 and max |d^S_i| (structure), ||d^G||_2 (ALE), ||(u, p)||_2 (fluid);
    /// norms of the global vectors, independent of the numbering and the partition.
    double structure_l2 = 0, structure_max = 0, ale_l2 = 0, fluid_l2 = 0;
    /// The largest |dV - dt (Q_in - Q_out)| / (dt Q_in) over the steps with inflow.
    double max_mass_imbalance = 0;
    /// At the end, with a rigid obstacle: the fluid's force on obstacle and structure (drag, lift
    /// [, z]); with a monitor point: its displacement. Empty otherwise.
    std::vector<double> obstacle_force, monitor_displacement;
  };

  FsiRunSummary run_condensed_fsi(const FsiParameters& parameters, MPI_Comm comm);
} // namespace physics::fsi
