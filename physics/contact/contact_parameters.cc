// The contact app's parameter file: declarations (with documentation, shown by --help and
// --print-parameters) and range checks with one-line errors naming the parameter.
#include "contact/contact_problem.h"

#include "common/parameter_checks.h"

#include <deal.II/base/utilities.h>

#include <stdexcept>

namespace physics::contact
{
  using dealii::Patterns::Anything;
  using dealii::Patterns::Double;
  using dealii::Patterns::Integer;
  using dealii::Patterns::Selection;

  void ContactParameters::declare(dealii::ParameterHandler& prm)
  {
    const ContactParameters d;
    prm.enter_subsection("Mesh");
    MeshParameters::declare_entries(prm, d,
                                    "Physical volumes (2D: surfaces) give the bodies, physical surfaces (2D: lines) "
                                    "the boundary ids below.");
    prm.declare_entry("Dimension", "2", Integer(2, 3), "Space dimension of the mesh.");
    prm.declare_entry(
        "Balance contact surfaces", "true", dealii::Patterns::Bool(),
        "Partition the mesh (METIS, one part per rank) so that every rank gets an equal share of "
        "the cells at the contact surfaces (the slave surface; with Contact surface ids all of "
        "them) as well as of all cells: the owner of a slave face evaluates its mortar integrals, "
        "so a rank holding the whole surface would do the contact work of all. false: equal "
        "numbers of cells only, which may put a whole surface on one rank.");
    prm.leave_subsection();

    prm.enter_subsection("Boundary ids");
    prm.declare_entry("Slave boundary id", "1", Integer(0, 255), "Contact surface carrying the multipliers.");
    prm.declare_entry("Master boundary id", "2", Integer(0, 255), "Opposite contact surface.");
    prm.declare_entry("Clamped boundary id", "3", Integer(-1, 255), "All displacement components zero (-1: none).");
    prm.declare_entry("Loaded boundary id", "4", Integer(0, 255),
                      "Face with the prescribed displacement or the pressure.");
    prm.declare_entry("Symmetry", "", Anything(),
                      "Roller conditions: comma-separated pairs 'id:component' (component 0=x, 1=y, 2=z), e.g. "
                      "'5:0, 6:1'. Empty: none.");
    prm.leave_subsection();

    MaterialParameters::declare(prm, d, "both bodies", "Pa", "kg/m^3 (used by dynamics and Gravity)", true);

    prm.enter_subsection("Loading");
    prm.declare_entry("Type", "displacement", Selection("displacement|pressure|none"),
                      "Prescribed displacement of the loaded face, a dead nominal pressure on it, or no load "
                      "(dynamics driven by the initial velocity; the loaded id is then ignored).");
    prm.declare_entry("Displacement", "0, -0.02", Anything(),
                      "Total prescribed displacement of the loaded face (dim comma-separated values, m).");
    prm.declare_entry("Pressure", "0", Double(), "Total nominal pressure (Pa, >= 0) for Type = pressure.");
    prm.declare_entry("Gravity", "", Anything(),
                      "Dead body force per unit mass on every body (dim comma-separated values, m/s^2, e.g. "
                      "'0, -9.81'; empty: none), with the Density of the Material section. Quasi-static: it "
                      "ramps with the load factor like the other loads. Dynamics: see Gravity ramp time.");
    prm.declare_entry("Gravity ramp time", "0", Double(),
                      "Dynamics: the body force grows linearly from zero at t = 0 to its full value at this time "
                      "(s, >= 0) and stays there; 0: full from the start. Bodies that start resting on each "
                      "other under a sudden load bounce; a ramp over a few of their vibration periods lets them "
                      "settle.");
    prm.declare_entry("Load steps", "4", Integer(1, 100000),
                      "Number of steps: equal quasi-static load increments, or time steps for generalized-alpha. "
                      "The load ramps linearly over all steps.");
    prm.leave_subsection();

    prm.enter_subsection("Time integration");
    prm.declare_entry("Scheme", "quasi-static", Selection("quasi-static|generalized-alpha"),
                      "quasi-static: load stepping without inertia. generalized-alpha: implicit dynamics "
                      "(Chung-Hulbert), contact forces at the same generalized midpoint as the internal forces, "
                      "contact constraints at the end of the step.");
    prm.declare_entry("Time step", "1e-3", Double(), "dt in s (> 0; generalized-alpha).");
    prm.declare_entry("Spectral radius", "1", Double(),
                      "rho_inf in [0, 1]: 1 = no numerical dissipation (trapezoidal rule), smaller values damp "
                      "the highest frequencies.");
    prm.declare_entry("Initial velocity", "", Anything(),
                      "Initial velocity of the slave body (dim comma-separated values, m/s; empty: at rest). The "
                      "master body starts at rest. Multi-body contact: every body that is slave in some pair.");
    prm.leave_subsection();

    prm.enter_subsection("Contact");
    prm.declare_entry("Multipliers", "dual", Selection("dual|standard"),
                      "Lagrange multiplier shape functions (dual: D diagonal).");
    prm.declare_entry("Complementarity factor", "1", Double(),
                      "c_n = factor * E / h in the complementarity function (> 0).");
    prm.declare_entry("Search radius factor", "1", Double(),
                      "Face bounding boxes are enlarged by this times the face size (>= 0).");
    prm.declare_entry("Friction coefficient", "0", Double(),
                      "Coulomb friction coefficient mu (>= 0; 0: frictionless). Each active contact node "
                      "sticks (no relative slip in the step) or slips with tangential traction mu times the "
                      "contact pressure, decided with the active set in the semi-smooth Newton method.");
    prm.declare_entry("Tangential complementarity factor", "1", Double(),
                      "c_t = factor * E / h in the frictional complementarity function (> 0; steers the "
                      "stick/slip decision of the Newton iterates, not the solution).");
    prm.declare_entry("Prescribed slave nodes", "contact", Selection("contact|no contact"),
                      "Slave nodes whose every displacement component is prescribed (a contact surface that "
                      "meets a clamped or loaded face). contact: they carry a multiplier like any slave node "
                      "(it pushes on the master side); no contact: they never enter the active set (lambda = "
                      "0), which removes the clash of the two conditions at such a node. With standard "
                      "multipliers the active set can cycle at these nodes under 'contact'.");
    prm.declare_entry("Contact surface ids", "", Anything(),
                      "Multi-body contact: comma-separated boundary ids of the contact surfaces; every face with "
                      "one of them belongs to the body (material id, i.e. gmsh physical surface/volume) of its "
                      "cell. Empty: two bodies, the faces of 'Slave boundary id' against those of 'Master "
                      "boundary id'.");
    prm.declare_entry("Pairs", "auto", Anything(),
                      "With contact surface ids: 'auto' (every body against every other; the lower body id is "
                      "the slave, the log says which pairs) or comma-separated 'slave:master' material id pairs, "
                      "e.g. '1:3, 2:3'. A body may be slave in one pair and master in another.");
    prm.declare_entry(
        "Self-contact check ids", "", Anything(),
        "Comma-separated boundary ids whose faces (besides the contact surfaces) are checked for "
        "self-contact after every converged step (a body whose faces cross each other: 2D two "
        "segments, 3D an edge through a face). "
        "Self-contact is not handled: the run stops with an error.");
    prm.leave_subsection();

    d.solver.declare(prm, residual_fields());

    OutputParameters::declare(prm, d, "VTK (solution.pvd + pvtu per step), contact_nodes.csv");
  }

  namespace
  {
    /// Comma-separated boundary ids 0..255.
    std::vector<int> boundary_ids(const std::string& text, const std::string& parameter)
    {
      std::vector<int> ids;
      for (const auto& item : dealii::Utilities::split_string_list(text, ','))
        {
          std::size_t used = 0;
          int         id   = -1;
          try
            {
              id = std::stoi(item, &used);
            }
          catch (const std::exception&)
            {
              used = 0;
            }
          if (used != item.size() || id < 0 || id > 255)
            throw std::invalid_argument("parameter '" + parameter + "': expected comma-separated boundary ids 0..255, got '" +
                                        item + "'");
          ids.push_back(id);
        }
      return ids;
    }

    /// 'auto' (empty result) or comma-separated 'slave:master' material ids.
    std::vector<std::pair<int, int>> contact_pairs(const std::string& text)
    {
      std::vector<std::pair<int, int>> pairs;
      if (dealii::Utilities::trim(text) == "auto")
        return pairs;
      for (const auto& item : dealii::Utilities::split_string_list(text, ','))
        {
          const auto parts = dealii::Utilities::split_string_list(item, ':');
          try
            {
              if (parts.size() != 2)
                throw std::invalid_argument("");
              std::size_t a = 0, b = 0;
              const int   s = std::stoi(parts[0], &a), m = std::stoi(parts[1], &b);
              if (a != parts[0].size() || b != parts[1].size() || s < 0 || m < 0)
                throw std::invalid_argument("");
              pairs.emplace_back(s, m);
            }
          catch (const std::exception&)
            {
              throw std::invalid_argument("parameter 'Pairs': expected 'auto' or 'slave:master' material id pairs, got '" +
                                          item + "'");
            }
        }
      if (pairs.empty())
        throw std::invalid_argument("parameter 'Pairs': expected 'auto' or at least one 'slave:master' pair");
      return pairs;
    }
  } // namespace

  using parameters::numbers;
  using parameters::positive;
  using parameters::tolerance;

  void ContactParameters::parse(dealii::ParameterHandler& prm)
  {
    prm.enter_subsection("Mesh");
    parse_entries(prm);
    dimension               = prm.get_integer("Dimension");
    balance_contact_surface = prm.get_bool("Balance contact surfaces");
    prm.leave_subsection();

    prm.enter_subsection("Boundary ids");
    slave_id   = prm.get_integer("Slave boundary id");
    master_id  = prm.get_integer("Master boundary id");
    clamped_id = prm.get_integer("Clamped boundary id");
    loaded_id  = prm.get_integer("Loaded boundary id");
    symmetry.clear();
    for (const auto& item : dealii::Utilities::split_string_list(prm.get("Symmetry"), ','))
      {
        const auto parts = dealii::Utilities::split_string_list(item, ':');
        try
          {
            if (parts.size() != 2)
              throw std::invalid_argument("");
            const int id = std::stoi(parts[0]), c = std::stoi(parts[1]);
            if (id < 0 || id > 255 || c < 0 || c >= dimension)
              throw std::invalid_argument("");
            symmetry.push_back(id);
            symmetry.push_back(c);
          }
        catch (const std::exception&)
          {
            throw std::invalid_argument("parameter 'Symmetry': expected 'id:component' pairs with component < " +
                                        std::to_string(dimension) + ", got '" + item + "'");
          }
      }
    prm.leave_subsection();

    MaterialParameters::parse(prm, true);

    prm.enter_subsection("Loading");
    load_type = prm.get("Type");
    displacement = numbers(prm.get("Displacement"), "Displacement");
    if (load_type == "displacement" && static_cast<int>(displacement.size()) != dimension)
      throw std::invalid_argument("parameter 'Displacement': expected " + std::to_string(dimension) +
                                  " components, got " + std::to_string(displacement.size()));
    pressure = prm.get_double("Pressure");
    if (pressure < 0)
      throw std::invalid_argument("parameter 'Pressure': expected a value >= 0, got " + std::to_string(pressure));
    load_steps = prm.get_integer("Load steps");
    gravity    = numbers(prm.get("Gravity"), "Gravity");
    if (!gravity.empty() && static_cast<int>(gravity.size()) != dimension)
      throw std::invalid_argument("parameter 'Gravity': expected " + std::to_string(dimension) +
                                  " components, got " + std::to_string(gravity.size()));
    gravity_ramp_time = prm.get_double("Gravity ramp time");
    if (!(gravity_ramp_time >= 0))
      throw std::invalid_argument("parameter 'Gravity ramp time': expected a value >= 0, got " +
                                  prm.get("Gravity ramp time"));
    prm.leave_subsection();

    prm.enter_subsection("Time integration");
    scheme           = prm.get("Scheme");
    time_step        = positive(prm.get_double("Time step"), "Time step");
    spectral_radius  = prm.get_double("Spectral radius");
    if (!(spectral_radius >= 0 && spectral_radius <= 1))
      throw std::invalid_argument("parameter 'Spectral radius': expected 0 <= rho <= 1, got " +
                                  std::to_string(spectral_radius));
    initial_velocity = numbers(prm.get("Initial velocity"), "Initial velocity");
    if (!initial_velocity.empty() && static_cast<int>(initial_velocity.size()) != dimension)
      throw std::invalid_argument("parameter 'Initial velocity': expected " + std::to_string(dimension) +
                                  " components, got " + std::to_string(initial_velocity.size()));
    if (!dynamic() && !initial_velocity.empty())
      throw std::invalid_argument("parameter 'Initial velocity': needs Scheme = generalized-alpha");
    if (!dynamic() && load_type == "none")
      throw std::invalid_argument("parameter 'Type' (Loading): 'none' needs Scheme = generalized-alpha");
    prm.leave_subsection();

    prm.enter_subsection("Contact");
    dual                   = prm.get("Multipliers") == "dual";
    complementarity_factor = positive(prm.get_double("Complementarity factor"), "Complementarity factor");
    search_radius_factor   = prm.get_double("Search radius factor");
    if (search_radius_factor < 0)
      throw std::invalid_argument("parameter 'Search radius factor': expected a value >= 0");
    friction_coefficient = prm.get_double("Friction coefficient");
    if (!(friction_coefficient >= 0))
      throw std::invalid_argument("parameter 'Friction coefficient': expected a value >= 0, got " +
                                  prm.get("Friction coefficient"));
    tangential_factor = positive(prm.get_double("Tangential complementarity factor"),
                                 "Tangential complementarity factor");
    prescribed_slave_contact = prm.get("Prescribed slave nodes") == "contact";
    surface_ids = boundary_ids(prm.get("Contact surface ids"), "Contact surface ids");
    watch_ids   = boundary_ids(prm.get("Self-contact check ids"), "Self-contact check ids");
    pairs       = contact_pairs(prm.get("Pairs"));
    if (!pairs.empty() && surface_ids.empty())
      throw std::invalid_argument("parameter 'Pairs': listed pairs need 'Contact surface ids'");
    prm.leave_subsection();

    solver.parse(prm, residual_fields());

    OutputParameters::parse(prm);
  }
} // namespace physics::contact
