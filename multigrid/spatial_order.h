// Z-order (Morton) keys of node coordinates: sorting nodes by them and cutting the order into equal
// chunks gives each chunk a compact piece of space, the cheap relative of recursive coordinate
// bisection that the system reader uses when it distributes a system over another number of
// ranks than its writer had (block_system_io.cc). And the nodes two fields share: where a field
// lives on another field's mesh (the FSI's ALE mesh is the fluid mesh), its aggregates can be the
// other field's (fully_coupled_amg.h, "block aggregates").
#pragma once

#include <cstdint>
#include <vector>

namespace multigrid
{
  /// The key of every node of every field: xyz[k] holds field k's coordinates column-major (n x
  /// dims[k], the layout of a Matrix Market array), dims[k] in 1..3 or 0 for a field without
  /// coordinates (its keys: empty). One cube around all fields' nodes serves every field, so that
  /// nodes close in space get close keys in every field alike; its side is the longest extent, so
  /// the keys' first bits split the longest direction (a tube is cut across its axis first).
  std::vector<std::vector<std::uint64_t>> morton_keys(const std::vector<std::vector<double>>& xyz,
                                                      const std::vector<int>&                 dims);

  /// For every node of `follower` (n_f x dim, node-major), the index of the `leader` node (n_l x
  /// dim, node-major) at the same position (within `tolerance`), or -1 where there is none. Sorting
  /// the leader's nodes makes it O((n_f + n_l) log n_l).
  std::vector<long> same_positions(const std::vector<double>& follower, const std::vector<double>& leader,
                                   int dim, double tolerance);
} // namespace multigrid
