#include "common/parameter_sections.h"

#include "common/parameter_checks.h"

#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace physics
{
  namespace
  {
    /// A double as a parameter default that reads back as the same value (std::to_string would
    /// print 1e-05 as "0.000010" and 3e6 as "3000000.000000").
    std::string text(double v)
    {
      std::ostringstream s;
      s.precision(12);
      s << v;
      return s.str();
    }

    std::string in_material(const std::string& entry) { return entry + " (Material)"; }
  } // namespace

  void MeshParameters::declare_entries(dealii::ParameterHandler& prm, const MeshParameters& d,
                                       const std::string& what_groups_mean)
  {
    prm.declare_entry("Mesh file", d.mesh_file,
                      dealii::Patterns::FileName(dealii::Patterns::FileName::FileType::input),
                      "gmsh .geo source (meshed on the fly with -setnumber refine N) or .msh file; written in a .prm "
                      "file: relative to that file's directory, given with --set (and this default): relative to "
                      "the working directory. " +
                          what_groups_mean + " Quadrilaterals/hexahedra.");
    prm.declare_entry("Gmsh refinement", std::to_string(d.gmsh_refinement), dealii::Patterns::Integer(1, 64),
                      "Value of the .geo variable 'refine'.");
    prm.declare_entry("Gmsh variables", "", dealii::Patterns::Anything(),
                      "Further variables of a .geo source, 'name=value, name=value' (gmsh -setnumber name "
                      "value; e.g. 'length=20' for meshes/fsi_tube_3d.geo); each must occur in the .geo file. "
                      "Empty: none.");
    prm.declare_entry("Global refinements", std::to_string(d.global_refinements), dealii::Patterns::Integer(0, 8),
                      "Uniform refinements after reading the mesh.");
  }

  void MeshParameters::parse_entries(const dealii::ParameterHandler& prm)
  {
    mesh_file          = prm.get("Mesh file");
    gmsh_refinement    = prm.get_integer("Gmsh refinement");
    gmsh_variables     = parse_gmsh_variables(prm.get("Gmsh variables"));
    global_refinements = prm.get_integer("Global refinements");
  }

  GmshSource MeshParameters::gmsh_source() const
  {
    GmshSource s(gmsh_refinement);
    s.variables = gmsh_variables;
    return s;
  }

  std::vector<std::pair<std::string, double>> MeshParameters::parse_gmsh_variables(const std::string& text)
  {
    const auto fail = [&](const std::string& why) {
      return std::invalid_argument("parameter 'Gmsh variables' (Mesh): expected 'name=value, name=value' (" + why +
                                   "), got '" + text + "'");
    };
    std::vector<std::pair<std::string, double>> variables;
    for (std::string item : dealii::Utilities::split_string_list(text, ','))
      {
        const auto equals = item.find('=');
        if (equals == std::string::npos)
          throw fail("no '=' in '" + item + "'");
        const std::string name  = dealii::Utilities::trim(item.substr(0, equals));
        const std::string value = dealii::Utilities::trim(item.substr(equals + 1));
        const bool        identifier =
            !name.empty() && !std::isdigit(static_cast<unsigned char>(name[0])) &&
            std::all_of(name.begin(), name.end(),
                        [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
        if (!identifier)
          throw fail("'" + name + "' is not a name");
        if (name == "refine")
          throw fail("'refine' is set by 'Gmsh refinement'");
        std::size_t used = 0;
        double      number;
        try
          {
            number = std::stod(value, &used);
          }
        catch (const std::exception&)
          {
            used = 0;
          }
        if (used == 0 || used != value.size() || !std::isfinite(number))
          throw fail("'" + value + "' is not a number");
        variables.emplace_back(name, number);
      }
    return variables;
  }

  void MaterialParameters::declare(dealii::ParameterHandler& prm, const MaterialParameters& d, const std::string& role,
                                   const std::string& stress_unit, const std::string& density_unit, bool with_density)
  {
    prm.enter_subsection("Material");
    prm.declare_entry("Law", d.law, dealii::Patterns::Selection("NeoHooke|SaintVenantKirchhoff"),
                      "Hyperelastic law of " + role + " (2D: plane strain): compressible Neo-Hooke or Saint "
                      "Venant-Kirchhoff.");
    prm.declare_entry("Young's modulus", text(d.youngs_modulus), dealii::Patterns::Double(),
                      "E in " + stress_unit + " (> 0).");
    prm.declare_entry("Poisson's ratio", text(d.poisson_ratio), dealii::Patterns::Double(), "nu (-1 < nu < 0.5).");
    if (with_density)
      prm.declare_entry("Density", text(d.density), dealii::Patterns::Double(),
                        "Reference mass density in " + density_unit + " (> 0).");
    prm.leave_subsection();
  }

  void MaterialParameters::parse(dealii::ParameterHandler& prm, bool with_density)
  {
    prm.enter_subsection("Material");
    law            = prm.get("Law");
    youngs_modulus = parameters::positive(prm.get_double("Young's modulus"), in_material("Young's modulus"));
    poisson_ratio  = parameters::poisson_ratio(prm.get_double("Poisson's ratio"), in_material("Poisson's ratio"));
    if (with_density)
      density = parameters::positive(prm.get_double("Density"), in_material("Density"));
    prm.leave_subsection();
  }

  void OutputParameters::declare(dealii::ParameterHandler& prm, const OutputParameters& d, const std::string& contents)
  {
    prm.enter_subsection("Output");
    prm.declare_entry("Directory", d.output_directory, dealii::Patterns::Anything(),
                      "Created if missing: the run log (run_log.jsonl), used_parameters.prm, " + contents +
                          ", exported systems.");
    prm.declare_entry("VTK", d.vtk ? "true" : "false", dealii::Patterns::Bool(),
                      "Write the VTK files (pvtu per step and a .pvd series).");
    prm.declare_entry("VTK interval", std::to_string(d.vtk_interval), dealii::Patterns::Integer(1, 100000),
                      "Write VTK every this many converged steps (and the last).");
    prm.declare_entry("Export systems", d.export_systems ? "true" : "false", dealii::Patterns::Bool(),
                      "Write every Newton step's BlockSystem to Directory/systems/stepS-newtonN (for "
                      "solve_block_system --system).");
    prm.declare_entry("Export aggregates", d.export_aggregates ? "true" : "false", dealii::Patterns::Bool(),
                      "Write the AMG aggregates of every Newton step's preconditioner (every field, every "
                      "coarse level) as VTK point sets Directory/aggregates/stepS-newtonN.pvtu (the "
                      "preset must build a blocked MueLu hierarchy: the saddle-point and fully coupled "
                      "presets); postprocess/aggregates.py renders and checks them.");
    prm.leave_subsection();
  }

  void OutputParameters::parse(dealii::ParameterHandler& prm)
  {
    prm.enter_subsection("Output");
    output_directory = prm.get("Directory");
    vtk              = prm.get_bool("VTK");
    vtk_interval     = prm.get_integer("VTK interval");
    export_systems   = prm.get_bool("Export systems");
    export_aggregates = prm.get_bool("Export aggregates");
    prm.leave_subsection();
  }

  void OutputParameters::set_exports(NewtonSettings& newton) const
  {
    newton.export_systems       = export_systems;
    newton.export_directory     = output_directory + "/systems";
    newton.export_aggregates    = export_aggregates;
    newton.aggregates_directory = output_directory + "/aggregates";
  }
} // namespace physics
