#include "spatial_order.h"

#include <algorithm>
#include <array>
#include <limits>

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
} // namespace multigrid
