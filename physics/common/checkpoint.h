// Checkpoint/restart of a stepped run (step_driver.h): what a converged step leaves behind so
// that a killed run can resume there and end as an uninterrupted one would.
//
// A checkpoint is a directory
//   checkpoint.bin   rank 0: the kind of problem, the number of ranks, and the named numbers,
//                    number lists and texts every rank shares (the step driver's counters, the
//                    run log so far, the VTK series' entries)
//   rank_K.bin       rank K: its named local arrays, e.g. the locally owned entries of each
//                    distributed vector in the order of the owned index set
// written under a temporary name and renamed into place only when every rank's file is complete,
// so an interrupted write never leaves a checkpoint that looks whole. A restart needs the same
// problem (same kind, DOFs, mesh) on the same number of ranks: the partition is deterministic, so
// each rank gets back exactly the rows it wrote; anything else is refused with a one-line error.
#pragma once

#include <deal.II/lac/trilinos_vector.h>

#include <mpi.h>

#include <map>
#include <string>
#include <vector>

namespace physics
{
  class Checkpoint
  {
  public:
    Checkpoint() = default;
    /// `kind` says which problem wrote it (class, dimension, sizes): a restart checks it.
    explicit Checkpoint(std::string kind)
        : kind_(std::move(kind))
    {
    }
    const std::string& kind() const { return kind_; }

    // Shared data: the same on every rank (rank 0 writes it).
    void                       set(const std::string& key, double value) { numbers_[key] = {value}; }
    void                       set(const std::string& key, std::vector<double> values) { numbers_[key] = std::move(values); }
    void                       set_text(const std::string& key, std::string value) { texts_[key] = std::move(value); }
    double                     number(const std::string& key) const;
    const std::vector<double>& numbers(const std::string& key) const;
    const std::string&         text(const std::string& key) const;

    // This rank's data.
    void                       set_local(const std::string& key, std::vector<double> values) { local_[key] = std::move(values); }
    const std::vector<double>& local(const std::string& key) const;
    /// The locally owned entries of `v` (and the owned index set's size, checked on restore).
    void store(const std::string& key, const dealii::TrilinosWrappers::MPI::Vector& v);
    /// Sets the owned entries of `v` (already laid out on the run's partition) from store().
    void restore(const std::string& key, dealii::TrilinosWrappers::MPI::Vector& v) const;
    /// This rank's sparse entries (DOF -> value, e.g. its share of a contact force) and back.
    void store(const std::string& key, const std::map<dealii::types::global_dof_index, double>& entries);
    void restore(const std::string& key, std::map<dealii::types::global_dof_index, double>& entries) const;

    /// Writes the checkpoint into `directory` (collective; atomically, see above). An existing
    /// checkpoint of that name is replaced.
    void write(const std::string& directory, MPI_Comm comm) const;
    /// Reads `directory` (collective). Throws std::invalid_argument "--restart 'DIR': ..." for a
    /// directory that is not a complete checkpoint, one of another kind than `expected_kind`, or
    /// one written on another number of ranks.
    static Checkpoint read(const std::string& directory, const std::string& expected_kind, MPI_Comm comm);

  private:
    const std::vector<double>& find(const std::map<std::string, std::vector<double>>& map, const std::string& key,
                                    const char* what) const;

    std::string                                kind_;
    std::map<std::string, std::vector<double>> numbers_;
    std::map<std::string, std::string>         texts_;
    std::map<std::string, std::vector<double>> local_;
    std::string                                source_; ///< the directory it was read from (messages)
  };

  /// The checkpoints of a run: `root`/step_NNNNNN, the newest named in `root`/latest (written
  /// atomically after the checkpoint is complete); older ones are removed once a newer one is in
  /// place, so a run keeps one checkpoint.
  class CheckpointSeries
  {
  public:
    explicit CheckpointSeries(std::string root)
        : root_(std::move(root))
    {
    }
    /// Writes the checkpoint of converged step `step` (collective) and returns its directory.
    std::string write(const Checkpoint& checkpoint, int step, MPI_Comm comm) const;
    /// The checkpoint `--restart PATH` means: PATH itself, or where PATH/latest points.
    static std::string resolve(const std::string& path);

  private:
    std::string root_;
  };
} // namespace physics
