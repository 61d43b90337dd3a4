#include "common/vtk_output.h"

#include "temporary_files.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace physics
{
  using namespace dealii;

  VtkSeries::VtkSeries(std::string directory, std::string base, MPI_Comm comm)
      : directory_(std::move(directory))
      , base_(std::move(base))
      , comm_(comm)
      , pvd_(directory_ + "/" + base_ + ".pvd")
  {
  }

  void VtkSeries::restore(const std::string& entries)
  {
    if (dealii::Utilities::MPI::this_mpi_process(comm_) == 0)
      pvd_.restore(entries);
  }

  template <int dim, int spacedim>
  void VtkSeries::write(const DataOut<dim, spacedim>& out, int step, double time)
  {
    const unsigned int rank = Utilities::MPI::this_mpi_process(comm_), ranks = Utilities::MPI::n_mpi_processes(comm_);
    const std::string  stem = base_ + "_" + Utilities::int_to_string(step, 4);
    auto               piece = [&](unsigned int r) { return stem + "." + std::to_string(r) + ".vtu"; };
    write_atomically(directory_ + "/" + piece(rank), [&](std::ostream& s) { out.write_vtu(s); });
    // The record names every piece: all of them must exist before it does.
    MPI_Barrier(comm_);
    if (rank == 0)
      {
        std::vector<std::string> pieces;
        for (unsigned int r = 0; r < ranks; ++r)
          pieces.push_back(piece(r));
        write_atomically(directory_ + "/" + stem + ".pvtu", [&](std::ostream& s) { out.write_pvtu_record(s, pieces); });
        pvd_.add(time, stem + ".pvtu");
      }
  }

  template <int dim>
  void SolidOutputFields<dim>::attach(DataOut<dim>& out, const DoFHandler<dim>& dof_handler, const SolidModel<dim>& model,
                                      const TrilinosWrappers::MPI::Vector& u)
  {
    const auto& tria = dof_handler.get_triangulation();
    cell_cauchy_stress(dof_handler, model, u, sigma_, von_mises_);
    partition_.reinit(tria.n_active_cells());
    for (const auto& cell : tria.active_cell_iterators())
      partition_(cell->active_cell_index()) = cell->subdomain_id();

    out.add_data_vector(u, std::vector<std::string>(dim, "displacement"), DataOut<dim>::type_dof_data,
                        std::vector<DataComponentInterpretation::DataComponentInterpretation>(
                            dim, DataComponentInterpretation::component_is_part_of_vector));
    const char* axes = "xyz";
    for (unsigned int a = 0; a < dim; ++a)
      for (unsigned int b = a; b < dim; ++b)
        out.add_data_vector(sigma_[a * dim + b], std::string("cauchy_stress_") + axes[a] + axes[b],
                            DataOut<dim>::type_cell_data);
    out.add_data_vector(von_mises_, "von_mises", DataOut<dim>::type_cell_data);
    out.add_data_vector(partition_, "partition", DataOut<dim>::type_cell_data);
    // Each rank writes its own cells only, not its ghost layer (the pieces of all ranks then
    // cover the mesh exactly once).
    out.set_cell_selection([](const typename Triangulation<dim>::cell_iterator& cell) {
      return cell->is_active() && cell->is_locally_owned();
    });
  }

  template void VtkSeries::write(const DataOut<2, 2>&, int, double);
  template void VtkSeries::write(const DataOut<3, 3>&, int, double);
  template class SolidOutputFields<2>;
  template class SolidOutputFields<3>;
} // namespace physics
