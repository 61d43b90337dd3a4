#include "spatial_order.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

namespace multigrid
{
  std::vector<std::vector<std::uint64_t>> morton_keys(const std::vector<std::vector<double>>& xyz,
                                                      const std::vector<int>&                 dims)
  {
    std::array<double, 3> lo, hi;
    lo.fill(std::numeric_limits<double>::max());
    hi.fill(std::numeric_limits<double>::lowest());
    for (std::size_t k = 0; k < xyz.size(); ++k)
      {
        const std::size_t n = dims[k] > 0 ? xyz[k].size() / dims[k] : 0;
        for (int c = 0; c < dims[k]; ++c)
          for (std::size_t i = 0; i < n; ++i)
            {
              lo[c] = std::min(lo[c], xyz[k][c * n + i]);
              hi[c] = std::max(hi[c], xyz[k][c * n + i]);
            }
      }
    double side = 0;
    for (int c = 0; c < 3; ++c)
      if (hi[c] >= lo[c])
        side = std::max(side, hi[c] - lo[c]);

    // 21 bits per direction (3 x 21 in 64); bit b of every direction, from the highest, in turn.
    constexpr int                           bits = 21;
    constexpr double                        top  = (1u << bits) - 1;
    std::vector<std::vector<std::uint64_t>> keys(xyz.size());
    for (std::size_t k = 0; k < xyz.size(); ++k)
      {
        if (dims[k] <= 0)
          continue;
        const std::size_t n = xyz[k].size() / dims[k];
        keys[k].assign(n, 0);
        for (std::size_t i = 0; i < n; ++i)
          {
            std::array<std::uint64_t, 3> q{};
            for (int c = 0; c < dims[k]; ++c)
              q[c] = static_cast<std::uint64_t>(
                  std::clamp(side > 0 ? (xyz[k][c * n + i] - lo[c]) / side : 0.0, 0.0, 1.0) * top);
            for (int b = bits - 1; b >= 0; --b)
              for (int c = 0; c < dims[k]; ++c)
                keys[k][i] = (keys[k][i] << 1) | ((q[c] >> b) & 1u);
          }
      }
    return keys;
  }

  std::vector<long> same_positions(const std::vector<double>& follower, const std::vector<double>& leader,
                                   int dim, double tolerance)
  {
    // Positions on a grid of spacing `tolerance`: equal positions give equal cells; two positions
    // closer than the tolerance may straddle a cell boundary, so the neighbouring cells (3^dim
    // of them) are searched as well.
    using Cell = std::array<long long, 3>;
    auto cell  = [&](const std::vector<double>& x, std::size_t i) {
      Cell c{};
      for (int d = 0; d < dim; ++d)
        c[d] = std::llround(x[i * dim + d] / tolerance);
      return c;
    };
    const std::size_t        n_leader = leader.size() / dim;
    std::vector<std::size_t> order(n_leader);
    std::vector<Cell>        cells(n_leader);
    for (std::size_t i = 0; i < n_leader; ++i)
      cells[i] = cell(leader, i);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return cells[a] < cells[b]; });

    auto close = [&](std::size_t f, std::size_t l) {
      for (int d = 0; d < dim; ++d)
        if (std::abs(follower[f * dim + d] - leader[l * dim + d]) > tolerance)
          return false;
      return true;
    };
    const int         neighbours = dim == 1 ? 3 : dim == 2 ? 9 : 27;
    std::vector<long> match(follower.size() / dim, -1);
    for (std::size_t f = 0; f < match.size(); ++f)
      {
        const Cell centre = cell(follower, f);
        for (int n = 0; n < neighbours && match[f] < 0; ++n)
          {
            Cell c = centre;
            for (int d = 0, m = n; d < dim; ++d, m /= 3)
              c[d] += m % 3 - 1;
            auto it = std::lower_bound(order.begin(), order.end(), c,
                                       [&](std::size_t l, const Cell& key) { return cells[l] < key; });
            for (; it != order.end() && cells[*it] == c; ++it)
              if (close(f, *it))
                {
                  match[f] = static_cast<long>(*it);
                  break;
                }
          }
      }
    return match;
  }
} // namespace multigrid
