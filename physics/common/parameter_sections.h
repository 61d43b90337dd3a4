// The parameter sections every app shares, declared and read once:
//
//   subsection Mesh      the gmsh input (file, its 'refine' value, uniform refinements); apps with
//                        a generated geometry add their own entries to the same section
//   subsection Material  the solid's hyperelastic law: Law, Young's modulus, Poisson's ratio,
//                        Density (where the app integrates inertia)
//   subsection Output    Directory, VTK, VTK interval, Export systems
//
// An app's parameter struct derives from the pieces it uses, so the problem classes read
// `p.youngs_modulus`, `p.output_directory`, ... whatever the app. Each piece's `declare` takes the
// app's defaults (an object of the same struct) and enters/leaves its section itself, except
// MeshParameters::declare_entries, which an app calls inside its own "Mesh" section so it can
// add the entries of its generated geometry there.
#pragma once

#include "common/mesh_input.h"
#include "common/newton_solver.h"

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace physics
{
  struct MeshParameters
  {
    std::string mesh_file;              ///< .geo (meshed with gmsh) or .msh
    int         gmsh_refinement    = 1; ///< passed to gmsh as -setnumber refine N (.geo only)
    /// Further .geo variables, -setnumber NAME VALUE (.geo only; "Gmsh variables").
    std::vector<std::pair<std::string, double>> gmsh_variables = {};
    int         global_refinements = 0; ///< deal.II refinements after reading

    /// The four entries, in the current subsection (the app's "Mesh"); `what_groups_mean` says
    /// what the mesh's physical groups give the app (bodies, boundary ids).
    static void declare_entries(dealii::ParameterHandler& prm, const MeshParameters& defaults,
                                const std::string& what_groups_mean);
    void        parse_entries(const dealii::ParameterHandler& prm);
    GmshSource  gmsh_source() const;
    /// "name=value, name=value" (blanks allowed; empty: none); throws std::invalid_argument
    /// naming 'Gmsh variables' for anything else, or for 'refine' (that is 'Gmsh refinement').
    static std::vector<std::pair<std::string, double>> parse_gmsh_variables(const std::string& text);
  };

  struct MaterialParameters
  {
    std::string law            = "NeoHooke"; ///< a name make_material() knows
    double      youngs_modulus = 1.0;        ///< E
    double      poisson_ratio  = 0.3;        ///< nu
    double      density        = 1.0;        ///< reference mass density (dynamics only)

    /// The "Material" section. `units` names the unit system of the app ("Pa, kg/m^3", CGS, ...);
    /// `with_density`: the app integrates inertia (quasi-static apps do not declare it).
    static void declare(dealii::ParameterHandler& prm, const MaterialParameters& defaults, const std::string& role,
                        const std::string& stress_unit, const std::string& density_unit, bool with_density);
    /// Throws std::invalid_argument "parameter 'X' (Material): expected ..." for E <= 0, nu
    /// outside (-1, 0.5), density <= 0.
    void parse(dealii::ParameterHandler& prm, bool with_density);
  };

  struct OutputParameters
  {
    std::string output_directory = "output";
    bool        vtk              = true;
    int         vtk_interval     = 1; ///< write VTK every this many steps (and the last)
    bool        export_systems   = false;
    bool        export_aggregates = false;

    /// The "Output" section; `contents` lists what the app writes into the directory besides the
    /// run log ("VTK (solution.pvd + pvtu per load step)").
    static void declare(dealii::ParameterHandler& prm, const OutputParameters& defaults, const std::string& contents);
    void        parse(dealii::ParameterHandler& prm);

    /// Whether converged step `number` writes VTK (every vtk_interval-th and the last one).
    bool vtk_due(int number, bool last) const { return vtk && (number % vtk_interval == 0 || last); }
    /// Hands the exports (systems, aggregates) and their directories to the Newton solver.
    void set_exports(NewtonSettings& newton) const;
  };
} // namespace physics
