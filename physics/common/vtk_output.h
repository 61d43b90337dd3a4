// ParaView output shared by every problem class: one .pvtu record per output step, its .vtu
// pieces (one per rank, locally owned cells only), and a .pvd series listing the records with
// their times. Every file is written to a temporary name and renamed when complete, the record
// only after all pieces exist and the series only after the record, so an interrupted run never
// leaves a half-written file or a series entry that points to one.
#pragma once

#include "common/run_output.h"
#include "common/solid_mechanics.h"

#include <deal.II/numerics/data_out.h>

#include <mpi.h>

#include <string>
#include <vector>

namespace physics
{
  class VtkSeries
  {
  public:
    /// Files directory/base_NNNN.R.vtu, directory/base_NNNN.pvtu and directory/base.pvd.
    VtkSeries(std::string directory, std::string base, MPI_Comm comm);

    /// Writes the patches of `out` (build_patches() done) as step `step` at `time` (collective).
    template <int dim, int spacedim>
    void write(const dealii::DataOut<dim, spacedim>& out, int step, double time);

    /// The series' entries so far and back (checkpoint/restart: a resumed run's .pvd lists the
    /// records written before the checkpoint, then its own).
    std::string entries() const { return pvd_.entries(); }
    void        restore(const std::string& entries);

  private:
    std::string directory_, base_;
    MPI_Comm    comm_;
    PvdSeries   pvd_;
  };

  /// The fields every solid's output carries, kept alive for DataOut (which stores references):
  /// the displacement, cell averages of the Cauchy stress components and of the von Mises
  /// stress, and the MPI rank owning each cell.
  template <int dim>
  class SolidOutputFields
  {
  public:
    /// Adds the fields of `u` (ghosted) to `out` (attached to `dof_handler`); restricts `out`
    /// to the locally owned cells.
    void attach(dealii::DataOut<dim>& out, const dealii::DoFHandler<dim>& dof_handler, const SolidModel<dim>& model,
                const dealii::TrilinosWrappers::MPI::Vector& u);

  private:
    std::vector<dealii::Vector<float>> sigma_;
    dealii::Vector<float>              von_mises_, partition_;
  };
} // namespace physics
