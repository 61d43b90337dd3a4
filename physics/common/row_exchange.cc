#include "common/row_exchange.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace physics
{
  namespace
  {
    struct Triplet
    {
      GlobalIndex row, col;
      double      value;
    };

    /// Sends triplets[r] to rank r, returns everything received.
    std::vector<Triplet> all_to_all(const std::vector<std::vector<Triplet>>& outgoing, MPI_Comm comm)
    {
      int n_ranks = 1;
      MPI_Comm_size(comm, &n_ranks);
      std::vector<int> send_counts(n_ranks), recv_counts(n_ranks), send_offsets(n_ranks + 1, 0),
          recv_offsets(n_ranks + 1, 0);
      for (int r = 0; r < n_ranks; ++r)
        send_counts[r] = static_cast<int>(outgoing[r].size() * sizeof(Triplet));
      MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm);
      for (int r = 0; r < n_ranks; ++r)
        {
          send_offsets[r + 1] = send_offsets[r] + send_counts[r];
          recv_offsets[r + 1] = recv_offsets[r] + recv_counts[r];
        }
      std::vector<char> send(send_offsets[n_ranks]), recv(recv_offsets[n_ranks]);
      for (int r = 0; r < n_ranks; ++r)
        std::copy(reinterpret_cast<const char*>(outgoing[r].data()),
                  reinterpret_cast<const char*>(outgoing[r].data()) + send_counts[r], send.data() + send_offsets[r]);
      MPI_Alltoallv(send.data(), send_counts.data(), send_offsets.data(), MPI_BYTE, recv.data(), recv_counts.data(),
                    recv_offsets.data(), MPI_BYTE, comm);
      std::vector<Triplet> received(recv.size() / sizeof(Triplet));
      std::copy(recv.begin(), recv.end(), reinterpret_cast<char*>(received.data()));
      return received;
    }
  } // namespace

  unsigned int owning_rank(const std::vector<dealii::IndexSet>& owned_per_rank, GlobalIndex index)
  {
    for (unsigned int r = 0; r < owned_per_rank.size(); ++r)
      if (owned_per_rank[r].is_element(index))
        return r;
    return 0;
  }

  void add_unsorted_indices(dealii::IndexSet& set, std::vector<GlobalIndex> indices)
  {
    std::sort(indices.begin(), indices.end());
    indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
    set.add_indices(indices.begin(), indices.end());
  }

  RowPieces send_rows_to_owners(RowPieces rows, const std::function<unsigned int(GlobalIndex)>& owner,
                                MPI_Comm comm)
  {
    int n_ranks = 1, rank = 0;
    MPI_Comm_size(comm, &n_ranks);
    MPI_Comm_rank(comm, &rank);
    std::vector<std::vector<Triplet>> outgoing(n_ranks);
    for (auto it = rows.begin(); it != rows.end();)
      {
        const unsigned int to = owner(it->first);
        if (to == static_cast<unsigned int>(rank))
          {
            ++it;
            continue;
          }
        for (const auto& [col, value] : it->second)
          outgoing[to].push_back({it->first, col, value});
        it = rows.erase(it);
      }
    for (const auto& t : all_to_all(outgoing, comm))
      rows[t.row][t.col] += t.value;
    return rows;
  }

  std::map<GlobalIndex, double> send_entries_to_owners(const std::map<GlobalIndex, double>& entries,
                                                       const std::function<unsigned int(GlobalIndex)>& owner,
                                                       MPI_Comm comm)
  {
    int n_ranks = 1;
    MPI_Comm_size(comm, &n_ranks);
    std::vector<std::vector<Triplet>> outgoing(n_ranks);
    for (const auto& [row, value] : entries)
      outgoing[owner(row)].push_back({row, 0, value});
    std::map<GlobalIndex, double> result;
    for (const auto& t : all_to_all(outgoing, comm))
      result[t.row] += t.value;
    return result;
  }

  std::string lowest_rank_message(const std::string& local_message, MPI_Comm comm)
  {
    int rank = 0, n_ranks = 1;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &n_ranks);
    int first = local_message.empty() ? n_ranks : rank;
    MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm);
    if (first == n_ranks)
      return "";
    std::string message = local_message;
    int         length  = static_cast<int>(message.size());
    MPI_Bcast(&length, 1, MPI_INT, first, comm);
    message.resize(length);
    MPI_Bcast(message.data(), length, MPI_CHAR, first, comm);
    return message;
  }

  void throw_if_any_rank_failed(const std::string& local_error, MPI_Comm comm)
  {
    if (const std::string message = lowest_rank_message(local_error, comm); !message.empty())
      throw std::invalid_argument(message);
  }
} // namespace physics
