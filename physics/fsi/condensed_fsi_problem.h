// The condensed FSI problem class behind run_condensed_fsi (condensed_fsi.h explains the
// formulation): its set-up, interface maps and Newton system in condensed_fsi.cc, its time
// steps, Newton updates, Jacobian check and output in condensed_fsi_steps.cc.
#pragma once

#include "common/newton_solver.h"
#include "common/row_exchange.h"
#include "common/run_output.h"
#include "common/solid_dynamics.h"
#include "common/solid_mechanics.h"
#include "common/step_driver.h"
#include "common/vtk_output.h"
#include "fsi/ale_fluid.h"
#include "fsi/ale_mesh_motion.h"
#include "fsi/condensed_fsi.h"
#include "fsi/fsi_meshes.h"
#include "fsi/interface_nodes.h"

#include "block_system.h"

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/fully_distributed_tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace physics::fsi
{
  /// One code for 2D (the channel) and 3D (the tube); boundary ids as in fsi_meshes.h.
  template <int dim>
  class CondensedFsi : public SteppedProblem
  {
  public:
    static bool on_interface(dealii::types::boundary_id id) { return id == boundary::interface; }

    CondensedFsi(const FsiParameters& p, MPI_Comm comm);
    FsiRunSummary run();

    // The nonlinear problem of one time step (common/newton_solver.h, step_driver.h).
    std::vector<std::string> field_names() const override { return FsiParameters::residual_fields(); }
    Linearization            linearize(int iteration) override;
    void                     update(const multigrid::MultiVector& dx) override;
    void                     set_update_length(double step_length) override;
    void                     begin_step(double time, double step) override;
    void                     reset_step() override;
    void                     end_step(int number, double time) override;
    void                     write_output(int number, double time, bool last) override;
    // Checkpoint/restart (condensed_fsi_balance.cc): the three fields with their BDF histories,
    // the structure's generalized-alpha state, lambda_n, the balance and wall-profile records.
    std::string checkpoint_kind() const override;
    void        save_state(Checkpoint& checkpoint) const override;
    void        load_state(const Checkpoint& checkpoint) override;
    /// The state vectors a checkpoint holds (the fields at t_{n+1}, t_n, t_{n-1}), by name.
    static std::vector<std::pair<const char*, dealii::TrilinosWrappers::MPI::Vector CondensedFsi::*>> state_vectors();
    /// The CSV files rank 0 appends to per step: checkpoint key, file name, stream.
    static std::vector<std::tuple<std::string, std::string, std::ofstream CondensedFsi::*>> csv_files();

  private:
    void make_meshes();
    void setup_fields();
    /// Clamped structure DOFs and ALE DOFs fixed on the inlet/outlet planes, from owned-DOF
    /// constraints made consistent across ranks (common/distributed_mesh.h).
    void make_boundary_constraints();
    /// The fluid's Dirichlet velocities (homogeneous, for the Newton increment): no-slip on rigid
    /// walls and obstacles, the inlet with a prescribed inflow.
    void make_fluid_constraints();
    /// The inflow profile at full inflow on the owned inlet velocity DOFs, the fluid DOFs whose
    /// residual is the force on obstacle and structure, the monitor point's structure DOFs
    /// (condensed_fsi_forces.cc).
    void setup_inflow_and_monitors();
    /// The parabolic inflow at `time` (ramp included) into the iterate's inlet velocities.
    void apply_inflow(double time);
    /// Logs the fluid's force on obstacle and structure, from the converged step's unconstrained
    /// fluid residual `R_free`, and the monitor point's displacement (event "obstacle_forces");
    /// appends them to forces.csv.
    void        record_forces(int number, double time, const dealii::TrilinosWrappers::MPI::Vector& R_free);
    std::string forces_csv_header() const;
    /// The interface maps: fluid velocity DOF -> structure DOFs, ALE DOF -> structure DOFs (weights
    /// of P: matching nodes or dual mortar), and
    /// the numbering of the merged system (structure, fluid without the interface velocities,
    /// inner ALE DOFs). From an all-gather of the interface nodes each rank owns.
    void match_interface();
    /// The fluid interface velocities and ALE interface displacements from the structure.
    void sync_interface();
    /// R^F (and its Jacobian and shape derivative) at the current state, through `constraints`
    /// (null: the fluid's Dirichlet constraints).
    void assemble_fluid(dealii::TrilinosWrappers::MPI::Vector& R, dealii::TrilinosWrappers::SparseMatrix* K,
                        dealii::TrilinosWrappers::SparseMatrix*  S,
                        const dealii::AffineConstraints<double>* constraints = nullptr);
    multigrid::BlockSystem assemble(std::vector<double>& norms);
    /// The natural size of the ALE residual (Newton's relative tolerance counts against it):
    /// ||K_II d_I|| over the inner, movable ALE rows, the mesh's internal forces from its inner
    /// displacements, which the interface's share K_IGamma d_Gamma balances at convergence.
    double ale_residual_scale() const;
    /// The fluid's volume (on the moved mesh) and the flow rates through the inlet, the outlet
    /// and the interface (outward normals; the inlet's is counted as inflow) at the current state.
    struct FluidBalance
    {
      double volume = 0, inflow = 0, outflow = 0, wall_flux = 0;
    };
    FluidBalance fluid_balance() const;
    /// The outward wall displacement d^S . n averaged over the interface nodes of each station
    /// (the distinct axial positions x of the interface nodes), summed over the ranks.
    std::vector<double> wall_profile() const;
    /// Logs the step's mass balance and appends the wall profile to wall_displacement.csv.
    void record_step(int number, double time);
    /// Testing: the Newton matrix times a direction v against central differences of the
    /// residual along v (relative error per field, logged and printed).
    void check_jacobian();
    /// Field (0 structure, 1 fluid, 2 ALE) and field DOF of an owned row of the merged system.
    std::pair<int, GlobalIndex> field_dof(multigrid::GO g) const;
    multigrid::GO               fluid_gid(GlobalIndex f) const;
    multigrid::GO               mesh_gid(GlobalIndex m) const;
    bool is_interface_velocity(GlobalIndex f) const { return fluid_partner_.count(f) > 0; }

    const FsiParameters&       p_;
    MPI_Comm                   comm_;
    const unsigned int         rank_;
    dealii::ConditionalOStream pcout_;
    dealii::TimerOutput        timer_;

    dealii::parallel::fullydistributed::Triangulation<dim> fluid_tria_, solid_tria_;
    dealii::FESystem<dim>                                  fluid_fe_, vector_fe_;
    dealii::DoFHandler<dim>                                fluid_dofs_, mesh_dofs_, solid_dofs_;
    dealii::IndexSet fluid_owned_, fluid_relevant_, mesh_owned_, mesh_relevant_, solid_owned_,
        solid_relevant_, solid_ghosts_;
    std::vector<dealii::IndexSet>          solid_owned_per_rank_;
    dealii::AffineConstraints<double>      fluid_constraints_, solid_constraints_, mesh_free_;
    dealii::AffineConstraints<double>      fluid_free_; ///< none: the unconstrained residual (forces)
    dealii::TrilinosWrappers::SparseMatrix K_F_, S_F_, K_S_;
    SolidModel<dim>                        solid_model_;
    std::unique_ptr<SolidDynamics<dim>>    dynamics_;
    std::unique_ptr<AleMeshMotion<dim>>    mesh_motion_;
    FluidModel<dim>                        fluid_model_;

    /// Interface DOF -> structure DOF, for the whole interface on every rank (interface-sized,
    /// from the all-gather of match_interface; the merged numbering needs every rank's count).
    /// With dual mortar each DOF follows several structure DOFs (a row of P; interface_nodes.h).
    InterfacePartners fluid_partner_, mesh_partner_;
    std::vector<GlobalIndex>           removed_mesh_; ///< interface ALE DOFs, sorted, whole interface
    /// Clamped structure DOFs this rank meets: its locally relevant ones and those of the whole
    /// interface (a fluid rank meets them as partners of its interface DOFs).
    std::set<GlobalIndex>    solid_clamped_;
    std::vector<double>      solid_coordinates_; ///< owned structure nodes, node-major (rigid-body modes)
    std::set<GlobalIndex>    mesh_fixed_;        ///< locally relevant ALE DOFs on the inlet/outlet planes
    std::vector<GlobalIndex> mesh_inner_owned_;                      ///< ascending
    multigrid::GO            n_solid_ = 0, n_fluid_ = 0, n_mesh_ = 0; ///< merged block sizes

    // State: structure d^S, fluid (u, p), ALE d^G (owned) and their ghosted copies; the BDF
    // derivative of d^S on the structure numbering (the interface velocities, sync_interface)
    dealii::TrilinosWrappers::MPI::Vector d_S_, d_S_old_, d_S_older_, d_S_ghosted_, u_interface_ghosted_;
    dealii::TrilinosWrappers::MPI::Vector x_F_, x_F_old_, x_F_older_, x_F_ghosted_;
    dealii::TrilinosWrappers::MPI::Vector d_G_, d_G_old_, d_G_older_, d_G_ghosted_;
    /// Rates at t_n through the fluid's stencil (one-step-theta carries them): the interface
    /// velocity in the structure's numbering, d(u, p)/dt, the grid velocity.
    dealii::TrilinosWrappers::MPI::Vector d_S_rate_, x_F_rate_, d_G_rate_;
    std::map<GlobalIndex, double>         lambda_old_; ///< lambda_n on the owned structure interface DOFs
    // The step in progress and the Newton direction (line search)
    dealii::TrilinosWrappers::MPI::Vector d_S_begin_, x_F_begin_, d_G_begin_, dd_S_, dx_F_, dd_G_;
    double                                update_length_ = 1;
    int                                   steps_done_    = 0;
    double                                last_time_step_ = 0; ///< the last accepted step (0 before the first)
    multigrid::BlockSystem                system_;
    JsonLinesLog                          log_;
    std::unique_ptr<VtkSeries>            fluid_vtk_, solid_vtk_;
    std::vector<double>                   max_wall_displacement_;
    /// The fluid's bounding box; 1e-9 of its diagonal is the tolerance of position matching.
    dealii::Point<dim> fluid_low_, fluid_high_;
    double             geometry_tolerance_ = 0;
    /// The share of the condensed interface's couplings (owned fluid interface DOF, structure
    /// DOF of its row) whose two DOFs one rank owns: 1 where the partitions of the two meshes
    /// agree at the interface (fsi_meshes.h), over all ranks.
    double interface_couplings_on_rank_ = 1;
    /// An owned structure interface node: its first DOF, its station and its outward normal
    /// (away from the fluid's centre line, perpendicular to x).
    struct WallNode
    {
      GlobalIndex            dof     = 0;
      unsigned int           station = 0;
      dealii::Tensor<1, dim> outward;
    };
    std::vector<WallNode> wall_nodes_;
    std::vector<double>   station_x_;                         ///< ascending
    std::vector<int>      station_count_;                     ///< interface nodes per station, all ranks
    double                volume_old_ = 0, volume_older_ = 0; ///< fluid volume at t_n, t_{n-1}
    double                volume_rate_ = 0; ///< dV/dt at t_n through the fluid's stencil
    double                max_mass_imbalance_ = 0; ///< relative, over the steps with inlet pressure
    std::ofstream         wall_csv_;               ///< rank 0
    // Inflow, forces and monitor point (condensed_fsi_forces.cc)
    std::map<GlobalIndex, double> inflow_profile_; ///< owned inlet velocity DOFs -> value at full inflow
    bool                          has_obstacle_ = false; ///< fluid faces with boundary::obstacle exist
    std::vector<GlobalIndex>      force_dofs_;   ///< owned fluid velocity DOFs on obstacle and interface
    std::vector<GlobalIndex>      monitor_dofs_; ///< the monitor node's structure DOFs, on its owner
    std::vector<double>           last_force_, last_monitor_; ///< of the last converged step
    std::ofstream                 forces_csv_;                ///< rank 0
  };
} // namespace physics::fsi
