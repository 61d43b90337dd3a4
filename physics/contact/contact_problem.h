// Mortar contact of hyperelastic bodies, frictionless or with Coulomb friction (2D plane strain or
// 3D), any number of bodies, quasi-static
// (load stepping) or dynamic (generalized-alpha, common/time_integration.h): mesh from gmsh,
// semi-smooth Newton with the contact active set updated inside the Newton loop, each linear
// system solved by GMRES with a block-AMG preset of multigrid/.
#pragma once

#include "common/parameter_sections.h"
#include "common/solver_parameters.h"
#include "common/step_driver.h"
#include "contact/mortar_contact.h"

#include <deal.II/base/parameter_handler.h>

#include <mpi.h>

#include <string>
#include <vector>

namespace physics::contact
{
  /// Mesh (file, refinements), Material (both bodies) and Output come from the common sections.
  struct ContactParameters : MeshParameters, MaterialParameters, OutputParameters
  {
    ContactParameters()
        : MeshParameters{"meshes/two_blocks_2d.geo"}
        , MaterialParameters{"NeoHooke", 10e6, 0.3, 1000} // Pa, kg/m^3
        , OutputParameters{"output/contact"}
    {
    }
    int  dimension               = 2;
    bool balance_contact_surface = true; ///< partition: equal shares of the contact-surface cells
    // Boundary and material ids
    int              slave_id = 1, master_id = 2, clamped_id = 3, loaded_id = 4;
    std::vector<int> symmetry; ///< pairs (boundary id, component) with zero normal displacement
    // Loading
    std::string         load_type = "displacement"; ///< displacement | pressure | none
    std::vector<double> displacement{0.0, -0.02};   ///< total prescribed displacement of the loaded face
    double              pressure = 0.0;             ///< total nominal pressure on the loaded face
    std::vector<double> gravity;                    ///< body force per unit mass (empty: none)
    double              gravity_ramp_time = 0.0;    ///< dynamics: gravity grows linearly until then
    int                 load_steps = 4;             ///< load increments, or time steps (dynamics)
    // Time integration
    std::string         scheme = "quasi-static";    ///< quasi-static | generalized-alpha
    double              time_step = 1e-3, spectral_radius = 1.0;
    std::vector<double> initial_velocity;           ///< slave body (dynamics), empty: at rest
    // Contact
    bool   dual                   = true;
    double complementarity_factor = 1.0; ///< c_n = factor * E / h
    double search_radius_factor   = 1.0;
    double friction_coefficient   = 0.0; ///< Coulomb's mu (0: frictionless)
    double tangential_factor      = 1.0; ///< c_t = factor * E / h
    bool   prescribed_slave_contact = true; ///< fully prescribed slave nodes may enter the active set
    // Multi-body contact (empty surface_ids: the two-body mode of slave_id / master_id)
    std::vector<int>                 surface_ids; ///< contact surface boundary ids (bodies = material ids)
    std::vector<std::pair<int, int>> pairs;       ///< (slave body, master body); empty: automatic
    std::vector<int>                 watch_ids;   ///< boundary ids only checked for self-contact
    bool multi_body() const { return !surface_ids.empty(); }
    // Newton and linear solver
    SolverParameters solver{1e-8, 1e-12, 30, "emin(cheapsimple)", {}, 1e-8, 500, 100};

    bool dynamic() const { return scheme == "generalized-alpha"; }
    /// The residual fields Newton checks separately (Newton subsections of the same names):
    /// forces on the displacement DOFs, and the contact constraints (weighted gaps of active
    /// nodes, multipliers of inactive ones).
    static std::vector<std::string> residual_fields() { return {"displacement", "constraint"}; }

    static void declare(dealii::ParameterHandler& prm);
    /// Reads and checks every value; throws std::invalid_argument "parameter 'X': ..." for values
    /// out of range.
    void parse(dealii::ParameterHandler& prm);
  };

  /// What a run measured (for tests and the final summary).
  struct ContactRunSummary : RunSummary
  {
    std::vector<int>    active_set_sizes;            ///< per Newton step
    // Final state of the slave nodes, on rank 0 only (empty elsewhere), ordered by their
    // reference positions (independent of the partition)
    std::vector<std::array<double, 3>> slave_positions; ///< current, padded with 0 in 2D
    std::vector<double>                normal_pressure; ///< lambda_n
    std::vector<double>                weight;          ///< w_j = int Phi_j (current slave area share)
    std::vector<bool>                  active;
    std::vector<double>                tangential; ///< |lambda_tau|
    std::vector<bool>                  slip;       ///< active and sliding (frictionless: = active)
    double                             max_displacement = 0; ///< max |u| over all nodes
    double                             displacement_l2 = 0;  ///< ||u|| (global vector norm)
    long long slave_nodes          = 0; ///< all ranks
    long long max_slave_nodes_held = 0; ///< the most slave nodes one rank holds (own + ghost faces)
    /// Largest penetration max(0, -g~_j / w_j) over the covered slave nodes of all converged steps
    /// (without the released prescribed ones, "Contact/Prescribed slave nodes = no contact").
    double max_penetration = 0;
    // Dynamics: after each time step (index 0: the initial state); the potential of the body force
    // (gravity), and the energy dissipated by friction up to that step (sum over the steps and
    // active nodes of lambda_tau . u, see contact/coulomb_friction.h).
    std::vector<double> time, kinetic_energy, strain_energy, body_force_potential, friction_work;
  };

  /// Runs the whole simulation. Input errors (mesh, ids, parameters) throw std::invalid_argument
  /// with a one-line message naming the file or parameter.
  ContactRunSummary run_contact(const ContactParameters& parameters, MPI_Comm comm);
} // namespace physics::contact
