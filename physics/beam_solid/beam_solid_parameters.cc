// The beam_solid app's parameter file: declarations (shown by --help / --print-parameters) and
// range checks with one-line errors naming the parameter.
#include "beam_solid/beam_solid_problem.h"

#include "common/parameter_checks.h"

namespace physics::beam_solid
{
  using dealii::Patterns::Anything;
  using dealii::Patterns::Double;
  using dealii::Patterns::Integer;
  using dealii::Patterns::Selection;
  using parameters::numbers;
  using parameters::positive;
  using parameters::tolerance;

  void BeamSolidParameters::declare(dealii::ParameterHandler& prm)
  {
    const BeamSolidParameters d;
    prm.enter_subsection("Mesh");
    prm.declare_entry("Size", "1, 1, 1", Anything(),
                      "The solid is the generated box [0, a] x [0, b] x [0, c]: edge lengths in m (> 0).");
    prm.declare_entry("Cells", "4, 4, 4", Anything(), "Hexahedra per edge (3 integers >= 1).");
    prm.declare_entry(
        "Balance coupling cells", "true", dealii::Patterns::Bool(),
        "Partition the box (METIS, one part per rank) so that every rank gets an equal share of the "
        "cells the beams cross as well as of all cells: the coupling integrates over those cells, and "
        "their solid rows are the dense rows of the Schur complement the saddle-point presets form, "
        "so a rank with more of them assembles and stores more. false: equal numbers of cells only.");
    prm.leave_subsection();

    MaterialParameters::declare(prm, d, "the solid block", "N/m^2", "", false);

    prm.enter_subsection("Fibres");
    prm.declare_entry("Beam file", "", dealii::Patterns::FileName(dealii::Patterns::FileName::FileType::input),
                      "gmsh beam mesh (written in a .prm file: relative to that file's directory; given with --set: "
                      "relative to the working directory): a .geo (meshed with gmsh -1) or an ASCII msh 2.2 file whose "
                      "2-node line "
                      "elements are the beam elements: straight fibres, elements collinear where they meet (the "
                      "torsion-free beam model needs straight reference fibres). Empty: the generated fibre grid "
                      "below.");
    prm.declare_entry("Beam refinement", "1", Integer(1, 1000),
                      "Value of the .geo file's 'refine' constant when gmsh meshes it (ignored for .msh).");
    prm.declare_entry("Fibres in y", "3", Integer(0, 1000), "Fibres per row across the width (y).");
    prm.declare_entry("Fibres in z", "3", Integer(0, 1000), "Rows of fibres across the height (z).");
    prm.declare_entry("Elements per fibre", "8", Integer(1, 100000), "Beam elements along each fibre.");
    prm.declare_entry("Margin", "0.1", Double(),
                      "Distance of the outer fibres from the side faces, as a fraction of the width/height "
                      "(0 <= margin < 0.5). Fibres run from x = 0 to x = a.");
    prm.declare_entry("Tilt", "0", Double(),
                      "The fibres rise by this fraction of the height over their length (0: parallel to x; "
                      "fibres must stay inside the solid).");
    prm.declare_entry("Young's modulus", "10", Double(), "E_B in N/m^2 (> 0), torsion-free Kirchhoff-Love beams.");
    prm.declare_entry("Radius", "0.005", Double(), "Fibre radius in m (> 0): A = pi r^2, I = pi r^4 / 4.");
    prm.leave_subsection();

    prm.enter_subsection("Coupling");
    prm.declare_entry("Method", "mortar", Selection("mortar|gpts"),
                      "mortar: segment-based integration (beam elements split at solid cell faces); gpts: Gauss "
                      "point to segment (the beam's own Gauss points).");
    prm.declare_entry("Penalty", "10", Double(), "Penalty parameter eps in N/m (> 0).");
    prm.declare_entry("Gauss points", "6", Integer(1, 20), "Per beam element (gpts) or per segment (mortar).");
    prm.leave_subsection();

    prm.enter_subsection("Loading");
    prm.declare_entry("Traction", "1, 0, 0", Anything(),
                      "Dead nominal traction on the face x = a (3 values, N/m^2); the face x = 0 is clamped.");
    prm.declare_entry("Load steps", "1", Integer(1, 10000), "Equal load increments.");
    prm.leave_subsection();

    d.solver.declare(prm, residual_fields());

    OutputParameters::declare(prm, d, "VTK (solid.pvd with a pvtu per step, beams.pvd with a vtu per step)");
  }

  void BeamSolidParameters::parse(dealii::ParameterHandler& prm)
  {
    prm.enter_subsection("Mesh");
    size = numbers(prm.get("Size"), "Size", 3);
    for (const double v : size)
      positive(v, "Size");
    cells.clear();
    for (const double v : numbers(prm.get("Cells"), "Cells", 3))
      {
        if (!(v >= 1) || v != static_cast<int>(v))
          throw std::invalid_argument("parameter 'Cells': expected integers >= 1, got " + std::to_string(v));
        cells.push_back(static_cast<int>(v));
      }
    balance_coupling_cells = prm.get_bool("Balance coupling cells");
    prm.leave_subsection();

    MaterialParameters::parse(prm, false);

    prm.enter_subsection("Fibres");
    beam_file          = prm.get("Beam file");
    beam_refinement    = prm.get_integer("Beam refinement");
    fibres_y           = prm.get_integer("Fibres in y");
    fibres_z           = prm.get_integer("Fibres in z");
    elements_per_fibre = prm.get_integer("Elements per fibre");
    fibre_margin       = prm.get_double("Margin");
    if (!(fibre_margin >= 0 && fibre_margin < 0.5))
      throw std::invalid_argument("parameter 'Margin': expected 0 <= margin < 0.5, got " + std::to_string(fibre_margin));
    fibre_tilt          = prm.get_double("Tilt");
    beam_youngs_modulus = positive(prm.get_double("Young's modulus"), "Young's modulus (Fibres)");
    fibre_radius        = positive(prm.get_double("Radius"), "Radius");
    prm.leave_subsection();

    prm.enter_subsection("Coupling");
    coupling     = prm.get("Method");
    penalty      = positive(prm.get_double("Penalty"), "Penalty");
    gauss_points = prm.get_integer("Gauss points");
    prm.leave_subsection();

    prm.enter_subsection("Loading");
    traction   = numbers(prm.get("Traction"), "Traction", 3);
    load_steps = prm.get_integer("Load steps");
    prm.leave_subsection();

    solver.parse(prm, residual_fields());

    OutputParameters::parse(prm);
  }
} // namespace physics::beam_solid
