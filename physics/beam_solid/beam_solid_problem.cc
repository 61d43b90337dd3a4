#include "beam_solid/beam_solid_problem.h"

#include "beam_solid/beam_output.h"
#include "beam_solid/beam_partition.h"
#include "beam_solid/beam_solid_coupling.h"
#include "common/distributed_mesh.h"
#include "common/mesh_input.h"
#include "common/newton_solver.h"
#include "common/run_directory.h"
#include "common/run_output.h"
#include "common/solid_mechanics.h"
#include "common/step_driver.h"
#include "common/tpetra_bridge.h"
#include "common/vtk_output.h"

#include <Xpetra_MapFactory.hpp>
#include <Xpetra_MultiVectorFactory.hpp>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/fully_distributed_tria.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>

namespace physics::beam_solid
{
  using namespace dealii;
  using multigrid::GO;

  namespace
  {
    /// Calls visit(f, fibre) for every fibre f = j fibres_z + k of the parameters' bundle (fibres_y
    /// x fibres_z straight fibres from x = 0 to x = a, rising by tilt * c over their length; E
    /// elements each, global nodes f (E + 1) + i and elements f E + i) for which wanted(f) holds,
    /// one fibre at a time: no caller needs the whole bundle at once.
    template <typename Wanted, typename Visit>
    void for_each_fibre(const BeamSolidParameters& p, const Wanted& wanted, const Visit& visit)
    {
      auto coordinate = [&](int i, int n, double extent) {
        return n == 1 ? 0.5 * extent : extent * (p.fibre_margin + (1 - 2 * p.fibre_margin) * i / (n - 1.0));
      };
      for (int j = 0; j < p.fibres_y; ++j)
        for (int k = 0; k < p.fibres_z; ++k)
          {
            const BeamIndex f = j * p.fibres_z + k;
            if (!wanted(f))
              continue;
            const double y = coordinate(j, p.fibres_y, p.size[1]), z = coordinate(k, p.fibres_z, p.size[2]);
            BeamMesh     fibre;
            add_straight_fibre(fibre, Point<3>(0, y, z), Point<3>(p.size[0], y, z + p.fibre_tilt * p.size[2]),
                               p.elements_per_fibre);
            fibre.check_and_set_tangents("Fibres");
            visit(f, fibre);
          }
    }

    /// This rank's share (beam_partition.h) of the generated fibre bundle: only the fibres its
    /// node block meets, so no rank ever holds the whole bundle.
    DistributedBeam generate_fibres(const BeamSolidParameters& p, unsigned int rank, unsigned int n_ranks)
    {
      const BeamIndex n_elements = p.elements_per_fibre, n_fibres = p.fibres_y * p.fibres_z;
      DistributedBeam part = empty_part(n_fibres * (n_elements + 1), n_fibres * n_elements, rank, n_ranks);
      for_each_fibre(
          p,
          [&](BeamIndex f) {
            const BeamIndex first = f * (n_elements + 1);
            return first < part.end_owned && first + n_elements + 1 > part.first_owned;
          },
          [&](BeamIndex f, const BeamMesh& fibre) {
            add_share(fibre, f * (n_elements + 1), f * n_elements, part);
          });
      return part;
    }

    /// The whole beam mesh of a beam file, read on this rank alone (gmsh meshes a .geo here).
    BeamMesh read_whole_beam_file(const BeamSolidParameters& p)
    {
      return read_beam_mesh(gmsh_mesh(p.beam_file, 1, p.beam_refinement, p.output_directory, MPI_COMM_SELF),
                            p.beam_file);
    }

    class BeamSolidProblem : public SteppedProblem
    {
    public:
      BeamSolidProblem(const BeamSolidParameters& p, MPI_Comm comm);
      BeamSolidRunSummary run();

      // The nonlinear problem of one load step (common/newton_solver.h, step_driver.h).
      std::vector<std::string> field_names() const override { return BeamSolidParameters::residual_fields(); }
      Linearization            linearize(int iteration) override;
      void                     update(const multigrid::MultiVector& dx) override;
      void                     set_update_length(double step_length) override;
      void                     begin_step(double time, double step) override;
      void                     reset_step() override;
      void                     end_step(int, double) override {}
      void                     write_output(int number, double time, bool last) override;
      // Checkpoint/restart (quasi-static: the displacements and the output series are the state).
      std::string checkpoint_kind() const override
      {
        return "beam/solid (" + std::to_string(tria_.n_global_active_cells()) + " solid cells, " +
               std::to_string(dof_handler_.n_dofs()) + " solid DOFs, " + std::to_string(beam_.n_dofs()) +
               " beam DOFs)";
      }
      void save_state(Checkpoint& c) const override
      {
        c.store("beam_solid/u", u_);
        c.store("beam_solid/d_beam", d_beam_);
        c.set_text("beam_solid/solid_vtk", solid_vtk_->entries());
        c.set_text("beam_solid/beam_pvd", beam_pvd_->entries()); // rank 0's is the one written
      }
      void load_state(const Checkpoint& c) override
      {
        c.restore("beam_solid/u", u_);
        c.restore("beam_solid/d_beam", d_beam_);
        u_ghosted_      = u_;
        d_beam_ghosted_ = d_beam_;
        solid_vtk_->restore(c.text("beam_solid/solid_vtk"));
        if (rank_ == 0)
          beam_pvd_->restore(c.text("beam_solid/beam_pvd"));
      }

    private:
      void setup();
      /// Assembles the coupled Newton system (global numbering: beam, then solid) on its owners.
      multigrid::BlockSystem assemble(double load_factor);
      /// Beam rows (positions then tangents of the locally owned beam nodes) and their rigid-body
      /// modes, solid rows and theirs.
      void set_nullspaces(multigrid::BlockSystem& system) const;
      void final_state(BeamSolidRunSummary& summary);
      /// This rank's part of the beams (beam_partition.h): its share of the generated fibre grid,
      /// or of the beam file `whole` that rank 0 read (empty elsewhere).
      void setup_beams(BeamMesh whole);
      /// Is coupled-system DOF g a solid DOF with a Dirichlet constraint?
      bool constrained(GlobalIndex g) const
      {
        return g >= beam_.n_dofs() && constraints_.is_constrained(g - beam_.n_dofs());
      }

      const BeamSolidParameters& p_;
      MPI_Comm                   comm_;
      const unsigned int         rank_, n_ranks_;
      ConditionalOStream         pcout_;
      TimerOutput                timer_;

      parallel::fullydistributed::Triangulation<3> tria_;
      FESystem<3>                        fe_;
      DoFHandler<3>                      dof_handler_;
      IndexSet                           owned_, relevant_, ghosts_;
      AffineConstraints<double>          constraints_;
      DynamicSparsityPattern             pattern_;
      SolidModel<3>                      model_;

      DistributedBeam                    beam_; ///< this rank's elements and nodes (beam_partition.h)
      BeamSection                        section_;
      std::unique_ptr<BeamSolidCoupling> coupling_;
      RowPieces                          coupling_matrix_; ///< owned rows of eps B^T k^-1 B (constant)
      IndexSet                           beam_owned_, beam_ghosts_; ///< owned / read beam DOFs

      TrilinosWrappers::MPI::Vector u_, u_ghosted_;
      TrilinosWrappers::MPI::Vector d_beam_, d_beam_ghosted_; ///< beam DOFs: owned, and as read here
      JsonLinesLog                  log_;
      std::unique_ptr<VtkSeries>    solid_vtk_;
      std::unique_ptr<PvdSeries>    beam_pvd_;

      // The step in progress
      double                        load_factor_ = 0;
      TrilinosWrappers::MPI::Vector u_begin_; ///< state at the step's start (reset_step)
      TrilinosWrappers::MPI::Vector d_beam_begin_;
      multigrid::BlockSystem        system_;  ///< the last linearization
      /// The last update's direction (solid, beam) and its applied length (line search).
      TrilinosWrappers::MPI::Vector du_direction_;
      TrilinosWrappers::MPI::Vector d_beam_direction_;
      double                        update_length_ = 1;
    };

    BeamSolidProblem::BeamSolidProblem(const BeamSolidParameters& p, MPI_Comm comm)
        : p_(p)
        , comm_(comm)
        , rank_(Utilities::MPI::this_mpi_process(comm))
        , n_ranks_(Utilities::MPI::n_mpi_processes(comm))
        , pcout_(std::cout, rank_ == 0)
        , timer_(pcout_, TimerOutput::never, TimerOutput::wall_times)
        , tria_(comm)
        , fe_(FE_Q<3>(1), 3)
        , dof_handler_(tria_)
    {
    }

    void BeamSolidProblem::setup()
    {
      TimerOutput::Scope scope(timer_, "setup");
      prepare_output_directory(p_.output_directory, comm_);
      // Box with boundary ids 0..5 (x-, x+, y-, y+, z-, z+), built and partitioned by the group
      // roots only (common/distributed_mesh.h). With `Balance coupling cells` the roots also mark
      // the cells the beams cross (beam_partition.h), from the whole beam file they read (rank
      // 0 keeps it to distribute the beams) or fibre by fibre from the generated bundle, and the
      // partition shares those out evenly as well.
      BeamMesh                      whole_beams;
      std::unique_ptr<CrossedCells> crossed;
      CellMarker<3>                 coupling_cells;
      if (p_.balance_coupling_cells)
        coupling_cells = [&](const Triangulation<3>::active_cell_iterator& cell) {
          return crossed->contains(cell->center());
        };
      create_distributed_mesh<3>(
          tria_,
          [&](Triangulation<3>& box) {
            GridGenerator::subdivided_hyper_rectangle(
                box,
                {static_cast<unsigned>(p_.cells[0]), static_cast<unsigned>(p_.cells[1]),
                 static_cast<unsigned>(p_.cells[2])},
                Point<3>(), Point<3>(p_.size[0], p_.size[1], p_.size[2]), true);
            for (const auto& cell : box.active_cell_iterators()) // colorize also sets material ids
              cell->set_material_id(0);
            if (!p_.beam_file.empty() && (rank_ == 0 || p_.balance_coupling_cells))
              whole_beams = read_whole_beam_file(p_);
            if (!p_.balance_coupling_cells)
              return;
            crossed = std::make_unique<CrossedCells>(p_.size, p_.cells);
            if (p_.beam_file.empty())
              for_each_fibre(
                  p_, [](BeamIndex) { return true; },
                  [&](BeamIndex, const BeamMesh& fibre) { crossed->mark(fibre); });
            else
              crossed->mark(whole_beams);
          },
          0, coupling_cells);
      crossed.reset();
      if (rank_ != 0)
        whole_beams = BeamMesh();
      dof_handler_.distribute_dofs(fe_);
      owned_ = dof_handler_.locally_owned_dofs();
      DoFTools::extract_locally_relevant_dofs(dof_handler_, relevant_);
      // The strided maps of the block system need node-major solid DOFs (x, y, z consecutive).
      for (const auto& cell : dof_handler_.active_cell_iterators())
        if (!cell->is_artificial())
          for (const unsigned int v : cell->vertex_indices())
            if (cell->vertex_dof_index(v, 0) % 3 != 0 || cell->vertex_dof_index(v, 1) != cell->vertex_dof_index(v, 0) + 1 ||
                cell->vertex_dof_index(v, 2) != cell->vertex_dof_index(v, 0) + 2)
              throw std::runtime_error("solid DOFs are not numbered node by node");

      constraints_.reinit(relevant_);
      add_boundary_constraints(dof_handler_, 0, Functions::ZeroFunction<3>(3), constraints_);
      close_distributed_constraints(dof_handler_, relevant_, constraints_);
      pattern_.reinit(relevant_.size(), relevant_.size(), relevant_);
      DoFTools::make_sparsity_pattern(dof_handler_, pattern_, constraints_, false);
      SparsityTools::distribute_sparsity_pattern(pattern_, owned_, comm_, relevant_);
      const auto lame = LameParameters::from_young_poisson(p_.youngs_modulus, p_.poisson_ratio);
      model_.materials[0] = make_material<3>(p_.law, lame);

      setup_beams(std::move(whole_beams));
      section_ = BeamSection::circular(p_.beam_youngs_modulus, p_.fibre_radius);

      // The coupling is linear in the unknowns and tied to the reference configuration: its
      // matrix is built once. Rows of constrained solid DOFs are dropped (those keep K_S's
      // identity rows).
      Timer coupling_timer;
      coupling_ = std::make_unique<BeamSolidCoupling>(
          beam_, dof_handler_, p_.coupling == "gpts" ? CouplingMethod::gpts : CouplingMethod::mortar, p_.gauss_points,
          "Fibres", comm_);
      const auto        owned_per_rank = Utilities::MPI::all_gather(comm_, owned_);
      const GlobalIndex n_beam         = beam_.n_dofs();
      coupling_matrix_                 = coupling_->penalty_matrix(p_.penalty, [&](GlobalIndex g) {
        return g < n_beam ? beam_.owner(g / 6) : owning_rank(owned_per_rank, g - n_beam);
      });
      for (auto it = coupling_matrix_.begin(); it != coupling_matrix_.end();)
        it = constrained(it->first) ? coupling_matrix_.erase(it) : std::next(it);
      const double coupling_seconds = coupling_timer.wall_time();

      // Ghosts: what the solid assembly, the local rows of B and the coupling matrix read; of the
      // beams, the nodes of this rank's elements and the neighbours its rows of B couple to.
      ghosts_ = relevant_;
      ghosts_.add_indices(coupling_->solid_dofs().begin(), coupling_->solid_dofs().end());
      beam_ghosts_ = beam_.stored_dofs();
      beam_ghosts_.add_indices(coupling_->beam_dofs().begin(), coupling_->beam_dofs().end());
      std::vector<GlobalIndex> read, read_beam;
      for (const auto& [row, entries] : coupling_matrix_)
        for (const auto& [column, value] : entries)
          if (column >= n_beam)
            read.push_back(column - n_beam);
          else
            read_beam.push_back(column);
      add_unsorted_indices(ghosts_, std::move(read));
      add_unsorted_indices(beam_ghosts_, std::move(read_beam));
      beam_owned_ = beam_.owned_dofs();
      beam_ghosts_.add_indices(beam_owned_);
      d_beam_.reinit(beam_owned_, comm_);
      d_beam_ghosted_.reinit(beam_owned_, beam_ghosts_, comm_);
      u_.reinit(owned_, comm_);
      u_ghosted_.reinit(owned_, ghosts_, comm_);
      if (rank_ == 0)
        log_ = JsonLinesLog(p_.output_directory + "/run_log.jsonl");
      solid_vtk_ = std::make_unique<VtkSeries>(p_.output_directory, "solid", comm_);
      beam_pvd_  = std::make_unique<PvdSeries>(p_.output_directory + "/beams.pvd");
      pcout_ << "beam_solid: " << tria_.n_global_active_cells() << " solid cells (at most "
             << Utilities::MPI::max(tria_.n_active_cells(), comm_) << " stored on a rank), "
             << dof_handler_.n_dofs() << " solid DOFs, beams with " << beam_.n_elements
             << " elements (beam nodes stored on a rank: at most "
             << Utilities::MPI::max(beam_.node_ids.size(), comm_) << " of " << beam_.n_nodes << "), "
             << beam_.n_dofs() << " beam DOFs, " << coupling_->n_points() << " coupling points ("
             << p_.coupling << ", at most " << coupling_->max_points_per_rank() << " on a rank, "
             << coupling_seconds << " s), " << n_ranks_ << " ranks, preset " << p_.solver.preset << "\n";
    }

    void BeamSolidProblem::setup_beams(BeamMesh whole)
    {
      if (p_.beam_file.empty())
        beam_ = generate_fibres(p_, rank_, n_ranks_);
      else // rank 0 read the whole mesh with the solid's (setup()) and sends every rank its part
        beam_ = distribute_beam(whole, comm_);
    }

    multigrid::BlockSystem BeamSolidProblem::assemble(double load_factor)
    {
      const GO n_beam = beam_.n_dofs();
      // Solid: K_S, r_S (deal.II numbering), dead traction on x = a.
      model_.tractions.clear();
      model_.tractions[1] = Tensor<1, 3>({load_factor * p_.traction[0], load_factor * p_.traction[1],
                                          load_factor * p_.traction[2]});
      TrilinosWrappers::SparseMatrix K;
      K.reinit(owned_, owned_, pattern_, comm_);
      TrilinosWrappers::MPI::Vector r(owned_, comm_);
      u_ghosted_ = u_;
      assemble_solid(dof_handler_, model_, u_ghosted_, constraints_, r, &K);

      // Beam elements: computed by their owner (that of their first node), rows of the second
      // node sent to its owner where another rank owns it.
      d_beam_ghosted_ = d_beam_;
      RowPieces                     beam_rows;
      std::map<GlobalIndex, double> beam_residual;
      for (std::size_t e = 0; e < beam_.mesh.elements.size(); ++e)
        {
          std::array<GlobalIndex, 12> dof;
          std::array<double, 12>      d;
          for (int i = 0; i < 12; ++i)
            {
              dof[i] = 6 * beam_.global_node(e, i / 6) + i % 6;
              d[i]   = d_beam_ghosted_[dof[i]];
            }
          const auto ed = element_derivatives(beam_.mesh, e, section_, d);
          for (int i = 0; i < 12; ++i)
            {
              beam_residual[dof[i]] += ed.gradient[i];
              for (int j = 0; j < 12; ++j)
                beam_rows[dof[i]][dof[j]] += ed.hessian[12 * i + j];
            }
        }
      const auto beam_row_owner = [this](GlobalIndex row) { return beam_.owner(row / 6); };
      beam_rows                 = send_rows_to_owners(std::move(beam_rows), beam_row_owner, comm_);
      beam_residual             = send_entries_to_owners(beam_residual, beam_row_owner, comm_);

      // Coupling forces: the (owned rows of the) constant penalty matrix times the displacements.
      std::map<GlobalIndex, double> coupling_residual;
      for (const auto& [row, entries] : coupling_matrix_)
        {
          double& f = coupling_residual[row];
          for (const auto& [column, value] : entries)
            f += value * (column < static_cast<GlobalIndex>(n_beam) ? d_beam_ghosted_[column]
                                                                    : u_ghosted_[column - n_beam]);
        }

      // Rows of the merged system: owned beam DOFs, then owned solid DOFs.
      std::vector<GO>                   beam_gids, solid_gids;
      std::vector<FlatRow>              rows;
      std::vector<double>               rhs;
      for (GlobalIndex n = beam_.first_owned; n < beam_.end_owned; ++n)
        for (int k = 0; k < 6; ++k)
          beam_gids.push_back(6 * static_cast<GO>(n) + k);
      for (const auto i : owned_)
        solid_gids.push_back(n_beam + static_cast<GO>(i));
      // Columns of constrained solid DOFs are dropped: their increments are zero.
      auto add = [&](GO g, std::map<GO, double> entries, double residual) {
        for (const auto& piece : {&beam_rows, &coupling_matrix_})
          if (const auto it = piece->find(g); it != piece->end())
            for (const auto& [c, v] : it->second)
              if (!constrained(c))
                entries[c] += v;
        for (const auto& piece : {&beam_residual, &coupling_residual})
          if (const auto it = piece->find(g); it != piece->end())
            residual += it->second;
        rows.emplace_back(entries.begin(), entries.end());
        rhs.push_back(-residual);
      };
      for (const GO g : beam_gids)
        add(g, {}, 0.0);
      for (const GO g : solid_gids)
        {
          std::map<GO, double> entries;
          add_row(K, g - n_beam, [&](GlobalIndex c) { return static_cast<GO>(c) + n_beam; }, entries);
          add(g, std::move(entries), r[g - n_beam]);
        }
      std::vector<GO> all(beam_gids);
      all.insert(all.end(), solid_gids.begin(), solid_gids.end());
      auto A = matrix_from_rows(comm_, n_beam + static_cast<GO>(dof_handler_.n_dofs()), all, rows);
      // The rows go before the blocks are extracted: held through from_merged() they were the
      // assembly's peak.
      rows = {};
      beam_rows.clear();
      auto b = Xpetra::MultiVectorFactory<double, int, GO, multigrid::NO>::Build(A->getRowMap(), 1, true);
      {
        auto data = b->getDataNonConst(0);
        for (std::size_t i = 0; i < rhs.size(); ++i)
          data[i] = rhs[i];
      }
      std::vector<multigrid::BlockInfo> blocks(2);
      blocks[0].name          = "beam";
      blocks[0].dofs_per_node = 6;
      blocks[0].global_size   = n_beam;
      blocks[1].name          = "solid";
      blocks[1].dofs_per_node = 3;
      blocks[1].global_size   = dof_handler_.n_dofs();
      auto system = multigrid::BlockSystem::from_merged(teuchos_comm(comm_), blocks, {beam_gids, solid_gids}, A, b);
      set_nullspaces(system);
      return system;
    }

    void BeamSolidProblem::set_nullspaces(multigrid::BlockSystem& system) const
    {
      // Beam: translations move positions; an infinitesimal rotation w moves positions by w x X
      // and tangents by w x T (reference configuration).
      auto beam_modes = Xpetra::MultiVectorFactory<double, int, GO, multigrid::NO>::Build(system.block(0).map, 6, true);
      for (int m = 0; m < 6; ++m)
        {
          auto data = beam_modes->getDataNonConst(m);
          for (GlobalIndex n = beam_.first_owned, i = 0; n < beam_.end_owned; ++n, i += 6)
            {
              const std::size_t local = beam_.local_node(n);
              Tensor<1, 3> w, shift_x, shift_t;
              if (m < 3)
                shift_x[m] = 1.0;
              else
                {
                  w[m - 3] = 1.0;
                  shift_x  = cross_product_3d(w, Tensor<1, 3>(beam_.mesh.nodes[local]));
                  shift_t  = cross_product_3d(w, beam_.mesh.tangents[local]);
                }
              for (int c = 0; c < 3; ++c)
                {
                  data[i + c]     = shift_x[c];
                  data[i + 3 + c] = shift_t[c];
                }
            }
        }
      system.block(0).nullspace = beam_modes;
      // Solid: rigid-body modes from the vertex coordinates, in the order of the owned DOFs.
      const auto xyz            = owned_vertex_positions(dof_handler_, owned_);
      system.block(1).nullspace = multigrid::rigid_body_modes(system.block(1).map, 3, xyz);
      multigrid::set_node_coordinates(system.block(1), 3, xyz);
      // The beam nodes at their reference positions (the aggregates' pictures).
      std::vector<double> beam_xyz;
      for (GlobalIndex n = beam_.first_owned; n < beam_.end_owned; ++n)
        for (int c = 0; c < 3; ++c)
          beam_xyz.push_back(beam_.mesh.nodes[beam_.local_node(n)][c]);
      multigrid::set_node_coordinates(system.block(0), 3, beam_xyz);
    }

    void BeamSolidProblem::begin_step(double time, double /*step*/)
    {
      load_factor_  = time;
      u_begin_      = u_;
      d_beam_begin_ = d_beam_;
    }

    void BeamSolidProblem::reset_step()
    {
      u_      = u_begin_;
      d_beam_ = d_beam_begin_;
    }

    Linearization BeamSolidProblem::linearize(int /*iteration*/)
    {
      system_ = multigrid::BlockSystem(); // the last Newton matrix: freed before the next is built
      system_ = assemble(load_factor_);
      Linearization result;
      result.system         = &system_;
      result.residual_norms = system_.block_norms(*system_.rhs());
      return result;
    }

    void BeamSolidProblem::update(const multigrid::MultiVector& dx)
    {
      // Solid into u, beam into the beam vector (both: the owned rows of the increment).
      const GO   n_beam = beam_.n_dofs();
      const auto data   = dx.getData(0);
      const auto map    = dx.getMap();
      d_beam_direction_.reinit(beam_owned_, comm_);
      du_direction_.reinit(owned_, comm_);
      for (std::size_t i = 0; i < map->getNodeNumElements(); ++i)
        {
          const GO g = map->getGlobalElement(i);
          if (g < n_beam)
            d_beam_direction_[g] = data[i];
          else
            du_direction_[g - n_beam] = data[i];
        }
      du_direction_.compress(VectorOperation::insert);
      d_beam_direction_.compress(VectorOperation::insert);
      update_length_ = 0;
      set_update_length(1.0);
    }

    void BeamSolidProblem::set_update_length(double step_length)
    {
      const double change = step_length - update_length_;
      u_.add(change, du_direction_);
      d_beam_.add(change, d_beam_direction_);
      update_length_ = step_length;
    }

    BeamSolidRunSummary BeamSolidProblem::run()
    {
      setup();
      NewtonSettings newton_settings   = p_.solver.newton_settings(field_names());
      p_.set_exports(newton_settings);
      NewtonSolver      newton(newton_settings, p_.solver.load_preset(), p_.solver.solve_options(), log_, pcout_, timer_,
                               comm_);
      const StepsResult result = run_steps(*this, p_.solver.step_settings(1.0, 1.0 / p_.load_steps, p_.output_directory), newton, log_, pcout_);

      BeamSolidRunSummary summary;
      summary.beam_dofs       = beam_.n_dofs();
      summary.solid_dofs      = dof_handler_.n_dofs();
      summary.coupling_points = coupling_->n_points();
      summary.record(result);
      if (!result.converged)
        pcout_ << "Newton did not converge in load step " << result.steps + 1 << ": " << result.failure << "\n";
      final_state(summary);
      log_timer_summary(timer_, log_, std::cout, rank_ == 0, comm_);
      return summary;
    }

    void BeamSolidProblem::final_state(BeamSolidRunSummary& summary)
    {
      u_ghosted_      = u_;
      d_beam_ghosted_ = d_beam_;
      double gap      = 0;
      for (const auto& [node, g] : coupling_->gaps(d_beam_ghosted_, u_ghosted_))
        gap = std::max(gap, std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]));
      summary.max_gap               = Utilities::MPI::max(gap, comm_);
      summary.solid_displacement_l2 = u_.l2_norm();
      summary.beam_displacement_l2  = d_beam_.l2_norm();
      double sum = 0, count = 0;
      for (const auto& cell : dof_handler_.active_cell_iterators())
        if (!cell->is_artificial()) // every cell at an owned vertex is owned or a ghost
          for (const unsigned int v : cell->vertex_indices())
            if (std::abs(cell->vertex(v)[0] - p_.size[0]) < 1e-12 && owned_.is_element(cell->vertex_dof_index(v, 0)))
              {
                sum += u_[cell->vertex_dof_index(v, 0)];
                count += 1;
              }
      // (vertices are counted once per adjacent cell; the mean is unaffected on a uniform grid)
      summary.mean_end_displacement = Utilities::MPI::sum(sum, comm_) / Utilities::MPI::sum(count, comm_);
      summary.beam_first_dof        = static_cast<long long>(6 * beam_.first_owned);
      summary.beam_displacement.clear();
      for (const auto g : beam_owned_)
        summary.beam_displacement.push_back(d_beam_[g]);
    }

    void BeamSolidProblem::write_output(int step, double /*time*/, bool last)
    {
      if (!p_.vtk_due(step, last))
        return;
      TimerOutput::Scope scope(timer_, "output");
      u_ghosted_ = u_;
      DataOut<3> out;
      out.attach_dof_handler(dof_handler_);
      SolidOutputFields<3> solid;
      solid.attach(out, dof_handler_, model_, u_ghosted_);
      out.build_patches();
      solid_vtk_->write(out, step, step);

      // Beams: every rank writes its elements as line cells with the displacement and the
      // coupling force per unit length, lambda_j = eps / kappa_j g_j. lambda is known at the
      // owners of the nodes; it travels to the ghost nodes in the position slots of a vector of
      // the beam DOFs' layout.
      d_beam_ghosted_ = d_beam_;
      TrilinosWrappers::MPI::Vector lambda(beam_owned_, comm_), lambda_ghosted(beam_owned_, beam_ghosts_, comm_);
      for (const auto& [j, g] : coupling_->gaps(d_beam_ghosted_, u_ghosted_))
        {
          const auto   kappa = coupling_->kappa().find(j);
          const double scale = kappa != coupling_->kappa().end() && kappa->second > 0 ? p_.penalty / kappa->second : 0.0;
          for (int c = 0; c < 3; ++c)
            lambda[6 * j + c] = scale * g[c];
        }
      lambda.compress(VectorOperation::insert);
      lambda_ghosted = lambda;
      const std::size_t                  n_local = beam_.node_ids.size();
      std::vector<double>                dofs(6 * n_local);
      std::vector<std::array<double, 3>> line_load(n_local);
      for (std::size_t n = 0; n < n_local; ++n)
        for (int k = 0; k < 6; ++k)
          {
            const GlobalIndex g = 6 * beam_.node_ids[n] + k;
            dofs[6 * n + k]     = d_beam_ghosted_[g];
            if (k < 3)
              line_load[n][k] = lambda_ghosted[g];
          }
      const std::string stem = "beams_" + Utilities::int_to_string(step, 4);
      auto piece = [&](unsigned int r) { return stem + "." + std::to_string(r) + ".vtu"; };
      if (!beam_.mesh.elements.empty())
        write_beam_vtu(beam_.mesh, dofs, line_load, p_.output_directory + "/" + piece(rank_));
      // The record names the pieces of the ranks with elements; all of them exist before it does.
      const auto elements_per_rank = Utilities::MPI::gather(comm_, beam_.mesh.elements.size());
      if (rank_ == 0)
        {
          std::vector<std::string> pieces;
          for (unsigned int r = 0; r < n_ranks_; ++r)
            if (elements_per_rank[r] > 0)
              pieces.push_back(piece(r));
          write_beam_pvtu(pieces, p_.output_directory + "/" + stem + ".pvtu");
          beam_pvd_->add(step, stem + ".pvtu");
        }
    }
  } // namespace

  BeamSolidRunSummary run_beam_solid(const BeamSolidParameters& parameters, MPI_Comm comm)
  {
    return BeamSolidProblem(parameters, comm).run();
  }
} // namespace physics::beam_solid
