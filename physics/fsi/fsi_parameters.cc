// The fsi app's parameter file: declarations (shown by --help / --print-parameters) and range
// checks with one-line errors naming the parameter.
#include "common/parameter_checks.h"
#include "fsi/ale_mesh_motion.h"
#include "fsi/condensed_fsi.h"

#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace physics::fsi
{
  using dealii::Patterns::Bool;
  using dealii::Patterns::Double;
  using dealii::Patterns::Integer;
  using parameters::positive;

  void FsiParameters::declare(dealii::ParameterHandler& prm)
  {
    const FsiParameters d;
    prm.enter_subsection("Mesh");
    MeshParameters::declare_entries(
        prm, d,
        "Empty: the generated 2D channel (the entries below). Else fluid = physical volume (2D: surface) 1, "
        "structure = 2, one conforming mesh; physical surfaces (2D: lines) 1 inlet plane, 2 outlet plane, 4 "
        "rigid walls (no-slip, structure clamped), 5 the structure's outer surface, 6 a rigid obstacle (as "
        "4, its force logged); the interface is where the two volumes meet (meshes/fsi_tube_3d.geo, "
        "meshes/fsi_turek_hron.geo).");
    prm.declare_entry("Dimension", "2", Integer(2, 3), "Space dimension (3 needs a Mesh file).");
    prm.declare_entry("Length", std::to_string(d.length), Double(), "Channel length L (> 0; CGS: cm).");
    prm.declare_entry("Height", std::to_string(d.height), Double(),
                      "Channel height H between the walls (> 0).");
    prm.declare_entry("Wall thickness", std::to_string(d.wall_thickness), Double(),
                      "Thickness of each wall (> 0).");
    prm.declare_entry("Cells in x", std::to_string(d.cells_x), Integer(1, 100000),
                      "Cells along the channel (fluid and walls: the interface nodes match).");
    prm.declare_entry("Fluid cells in y", std::to_string(d.cells_fluid_y), Integer(1, 100000),
                      "Fluid cells across H.");
    prm.declare_entry("Wall cells in y", std::to_string(d.cells_wall_y), Integer(1, 100000),
                      "Structure cells across each wall.");
    prm.declare_entry("Wall cells in x", "0", Integer(0, 100000),
                      "Structure cells along each wall; 0: Cells in x (matching interface nodes). Another "
                      "number makes the interface meshes non-matching: needs Coupling/Interface = dual "
                      "mortar.");
    prm.leave_subsection();

    prm.enter_subsection("Fluid");
    prm.declare_entry("Density", "1", Double(), "rho_F (> 0; CGS: g/cm^3).");
    prm.declare_entry("Viscosity", "0.03", Double(), "Dynamic viscosity mu_F (> 0; CGS: P).");
    prm.declare_entry(
        "Stabilization with time step", d.tau_with_time_step ? "true" : "false", Bool(),
        "The PSPG/SUPG parameter tau_M = ((2/dt)^2 + 4|c|^2/h^2 + (4 nu/h^2)^2)^(-1/2) with its "
        "(2/dt)^2 term (the usual choice), or without it (the seeds' code's 'wo_dt' definitions: "
        "the stabilized discretization then does not depend on dt, and small steps keep the PSPG "
        "pressure stabilization, which tau_M -> dt/2 weakens as dt -> 0). Without it tau_M of fluid at rest "
        "is "
        "h^2 / (4 nu), far above dt where the flow starts suddenly: the pressure-pulse channel's Newton "
        "diverges in its first step (dt 1e-4 and 2.5e-5); the Turek-Hron FSI1 case converges either way.");
    prm.leave_subsection();

    MaterialParameters::declare(prm, d, "the walls", "dyn/cm^2 (CGS; 3e6 = 3e5 Pa)", "g/cm^3 (CGS)", true);

    prm.enter_subsection("ALE mesh");
    prm.declare_entry("Poisson ratio", "0.3", Double(),
                      "Of the pseudo-elastic mesh material (0 <= nu < 0.5).");
    prm.declare_entry("Stiffening exponent", "1", Double(),
                      "chi >= 0: cell stiffness (mean |K| / |K|)^chi, small cells move more rigidly.");
    prm.leave_subsection();

    prm.enter_subsection("Loading");
    prm.declare_entry("Inflow", "pressure pulse",
                      dealii::Patterns::Selection("pressure pulse|parabolic velocity"),
                      "What drives the flow through the inlet (boundary id 1, a plane normal to x): a "
                      "pressure pulse (Inlet pressure, Pulse duration; the pressure-wave tube and channel) "
                      "or a prescribed parabolic velocity profile along x (Mean inflow velocity, Inflow "
                      "ramp time; the Turek-Hron channel): 2D 1.5 U 4 s (1 - s) with s across the inlet's "
                      "extent in y, 3D 2 U (1 - r^2 / R^2) on a circular inlet of radius R.");
    prm.declare_entry("Inlet pressure", "1.3332e4", Double(),
                      "Pressure on the inlet x = 0 during the pulse (CGS: dyn/cm^2).");
    prm.declare_entry("Pulse duration", "3e-3", Double(),
                      "The inlet pressure acts for 0 < t <= this, then 0 (>= 0; s).");
    prm.declare_entry("Mean inflow velocity", "0.2", Double(),
                      "U, the mean velocity of the parabolic inflow (> 0; its peak is 1.5 U in 2D, 2 U in "
                      "3D).");
    prm.declare_entry("Inflow ramp time", "0", Double(),
                      "T >= 0: the parabolic inflow grows as (1 - cos(pi t / T)) / 2 for t < T (the "
                      "benchmark's smooth start), then stays; 0: full inflow from the first step.");
    prm.leave_subsection();

    prm.enter_subsection("Time");
    prm.declare_entry("Time step", "1e-4", Double(),
                      "dt (> 0; s). Fluid by 'Fluid scheme', structure generalized-alpha.");
    prm.declare_entry("End time", "1e-3", Double(), "Final time (> 0; s).");
    prm.declare_entry(
        "Fluid scheme", "BDF1", dealii::Patterns::Selection("BDF1|BDF2|one-step-theta"),
        "Time derivative of the fluid, the grid velocity and the interface velocity: backward Euler, "
        "BDF2 (second order, with the weights of unequal steps after a step cut; the first step takes "
        "the rest state as both earlier states) or one-step-theta (the seeds' fluid integrator, in rate "
        "form: x_{n+1} = x_n + dt (theta r_{n+1} + (1 - theta) r_n), the rates carried from step to "
        "step, zero at the start; every step size works).");
    prm.declare_entry("Theta", "0.5", Double(),
                      "theta of one-step-theta (1/2 <= theta <= 1): 1/2 the trapezoidal rule (second "
                      "order, no numerical damping), 1 backward Euler. Read only with that scheme.");
    prm.declare_entry(
        "Spectral radius", "1", Double(0, 1),
        "rho_inf of the structure's generalized-alpha (0 <= rho <= 1; 1: no numerical dissipation).");
    prm.leave_subsection();

    prm.enter_subsection("Coupling");
    prm.declare_entry("Shape derivatives", "true", Bool(),
                      "Include the fluid's derivatives with respect to the mesh displacement in the Jacobian "
                      "(false: Newton converges more slowly).");
    prm.declare_entry(
        "Interface", "matching nodes", dealii::Patterns::Selection("matching nodes|dual mortar"),
        "How the fluid's interface follows the structure's: node by node (the meshes must match there) or "
        "by dual mortar, P = D^-1 M with the fluid side as slave (non-matching meshes; on matching meshes "
        "P is the node map). The fluid interface velocities and ALE interface displacements are P times "
        "the structure's, the fluid's interface rows reach the structure as P^T R.");
    prm.declare_entry(
        "Check Jacobian", "false", Bool(),
        "Testing: at the start of time step 2, compare the Newton matrix times a direction with "
        "central differences of the residual; prints and logs the relative error per field.");
    prm.leave_subsection();

    d.solver.declare(prm, residual_fields());

    OutputParameters::declare(prm, d, "VTK (fluid.pvd and structure.pvd, a pvtu per step each)");
    prm.enter_subsection("Output");
    prm.declare_entry("Monitor point", "", dealii::Patterns::Anything(),
                      "Empty, or the reference coordinates (dim numbers, separated by commas or blanks) of a "
                      "structure mesh node whose displacement is logged per time step (the Turek-Hron "
                      "point A: 0.6, 0.2). "
                      "With a rigid obstacle (boundary id 6) the fluid's force on obstacle and structure "
                      "(drag, lift) is logged too; both go to Directory/forces.csv.");
    prm.leave_subsection();
  }

  void FsiParameters::parse(dealii::ParameterHandler& prm)
  {
    prm.enter_subsection("Mesh");
    parse_entries(prm);
    dimension = prm.get_integer("Dimension");
    if (dimension == 3 && mesh_file.empty())
      throw std::invalid_argument("parameter 'Mesh file' (Mesh): expected a mesh file with Dimension = 3 "
                                  "(the generated channel is 2D)");
    length         = positive(prm.get_double("Length"), "Length (Mesh)");
    height         = positive(prm.get_double("Height"), "Height (Mesh)");
    wall_thickness = positive(prm.get_double("Wall thickness"), "Wall thickness (Mesh)");
    cells_x        = prm.get_integer("Cells in x");
    cells_fluid_y  = prm.get_integer("Fluid cells in y");
    cells_wall_y   = prm.get_integer("Wall cells in y");
    cells_wall_x   = prm.get_integer("Wall cells in x");
    prm.leave_subsection();

    prm.enter_subsection("Fluid");
    fluid_density   = positive(prm.get_double("Density"), "Density (Fluid)");
    fluid_viscosity    = positive(prm.get_double("Viscosity"), "Viscosity (Fluid)");
    tau_with_time_step = prm.get_bool("Stabilization with time step");
    prm.leave_subsection();

    MaterialParameters::parse(prm, true);

    prm.enter_subsection("ALE mesh");
    ale_poisson_ratio = prm.get_double("Poisson ratio");
    ale_stiffening    = prm.get_double("Stiffening exponent");
    MeshMotionSettings{ale_poisson_ratio, ale_stiffening}.check();
    prm.leave_subsection();

    prm.enter_subsection("Loading");
    parabolic_inflow = prm.get("Inflow") == "parabolic velocity";
    inlet_pressure   = prm.get_double("Inlet pressure");
    pulse_duration   = prm.get_double("Pulse duration");
    if (!(pulse_duration >= 0))
      throw std::invalid_argument("parameter 'Pulse duration' (Loading): expected a value >= 0");
    mean_inflow_velocity = positive(prm.get_double("Mean inflow velocity"), "Mean inflow velocity (Loading)");
    inflow_ramp_time     = prm.get_double("Inflow ramp time");
    if (!(inflow_ramp_time >= 0))
      throw std::invalid_argument("parameter 'Inflow ramp time' (Loading): expected a value >= 0");
    prm.leave_subsection();

    prm.enter_subsection("Time");
    time_step       = positive(prm.get_double("Time step"), "Time step (Time)");
    end_time        = positive(prm.get_double("End time"), "End time (Time)");
    spectral_radius = prm.get_double("Spectral radius");
    const std::string scheme = prm.get("Fluid scheme");
    fluid_scheme             = scheme == "BDF2"             ? FluidTimeScheme::bdf2
                               : scheme == "one-step-theta" ? FluidTimeScheme::one_step_theta
                                                            : FluidTimeScheme::bdf1;
    fluid_theta              = prm.get_double("Theta");
    if (fluid_scheme == FluidTimeScheme::one_step_theta && !(fluid_theta >= 0.5 && fluid_theta <= 1))
      throw std::invalid_argument("parameter 'Theta' (Time): expected 1/2 <= theta <= 1, got " +
                                  prm.get("Theta"));
    prm.leave_subsection();

    prm.enter_subsection("Coupling");
    shape_derivatives = prm.get_bool("Shape derivatives");
    dual_mortar       = prm.get("Interface") == "dual mortar";
    check_jacobian    = prm.get_bool("Check Jacobian");
    prm.leave_subsection();

    solver.parse(prm, residual_fields());

    OutputParameters::parse(prm);
    prm.enter_subsection("Output");
    monitor_point = parse_point(prm.get("Monitor point"), dimension);
    prm.leave_subsection();
  }

  std::vector<double> FsiParameters::parse_point(const std::string& text, int dim)
  {
    std::vector<double> point;
    if (text.find_first_not_of(" \t") == std::string::npos)
      return point;
    const auto bad = [&] {
      return std::invalid_argument("parameter 'Monitor point' (Output): expected " + std::to_string(dim) +
                                   " numbers (separated by commas or blanks), got '" + text + "'");
    };
    std::string separated = text; // commas or blanks between the numbers
    std::replace(separated.begin(), separated.end(), ',', ' ');
    std::istringstream in(separated);
    std::string        item;
    while (in >> item)
      {
        std::size_t end = 0;
        try
          {
            point.push_back(std::stod(item, &end));
          }
        catch (const std::exception&)
          {
            throw bad();
          }
        if (end != item.size() || !std::isfinite(point.back()))
          throw bad();
      }
    if (point.size() != static_cast<std::size_t>(dim))
      throw bad();
    return point;
  }
} // namespace physics::fsi
