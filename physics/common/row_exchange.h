// Sending assembled pieces to the rank that owns them. Surface terms (contact, coupling) are
// integrated where the slave face lives, but their rows belong to whichever rank owns the DOF;
// these helpers route (row, column, value) triplets and (row, value) pairs to the owners, where
// they are summed. One all-to-all of counts and one of data per call.
#pragma once

#include <deal.II/base/index_set.h>
#include <deal.II/base/types.h>

#include <mpi.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace physics
{
  using GlobalIndex = dealii::types::global_dof_index;
  using RowPieces   = std::map<GlobalIndex, std::map<GlobalIndex, double>>;

  /// The rank whose entry of `owned_per_rank` (all ranks' owned index sets, e.g. from
  /// Utilities::MPI::all_gather) contains `index`; 0 if none does.
  unsigned int owning_rank(const std::vector<dealii::IndexSet>& owned_per_rank, GlobalIndex index);

  /// Adds `indices` (any order, repeats allowed: the columns a rank's rows read) to `set`, sorted
  /// and without repeats in one call. IndexSet::add_index of an index below the set's last one
  /// inserts a range into the middle of its list (compress() merges only later), so adding
  /// unsorted indices one by one costs O(n^2): 17 % of a 1-rank run of the 3D contact benchmark.
  void add_unsorted_indices(dealii::IndexSet& set, std::vector<GlobalIndex> indices);

  /// Rows not owned here are sent to `owner(row)` and summed there; returns the owned rows.
  /// The rows this rank owns stay in place and only the others travel, so a caller that moves
  /// its pieces in (a whole merged matrix, mostly owned rows) holds them once, not three times
  /// (pieces, triplets in flight and their sums).
  RowPieces send_rows_to_owners(RowPieces rows, const std::function<unsigned int(GlobalIndex)>& owner,
                                MPI_Comm comm);

  /// The same for a sparse vector.
  std::map<GlobalIndex, double> send_entries_to_owners(const std::map<GlobalIndex, double>& entries,
                                                       const std::function<unsigned int(GlobalIndex)>& owner,
                                                       MPI_Comm comm);

  /// Collective: "" on every rank when `local_message` is empty everywhere, otherwise the
  /// message of the lowest rank with a non-empty one.
  std::string lowest_rank_message(const std::string& local_message, MPI_Comm comm);

  /// Collective: when `local_error` is non-empty on some rank, every rank throws
  /// std::invalid_argument with the message of the lowest such rank (input errors found by one
  /// rank's share of the work reach the root's error line and nobody waits forever).
  void throw_if_any_rank_failed(const std::string& local_error, MPI_Comm comm);
} // namespace physics
