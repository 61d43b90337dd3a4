// The inner product of one sparse row with a dense vector, the kernel of the project's triangular
// solves (ilu0_smoother.h) and Gauss-Seidel sweeps (gauss_seidel_smoother.h).
//
// Why not one running sum, as Ifpack2's and Kokkos Kernels' loops keep: each addition would wait
// for the one before (about four cycles each), so that a row of 80 entries costs the latency of
// 80 dependent additions, while its loads and products could go at once. Four independent partial
// sums let the additions overlap; the result differs from the sequential sum by round-off only.
#pragma once

#include "types.h"

#include <cstddef>

namespace multigrid
{
  /// sum_k values[k] x[columns[k]], k < length, in four partial sums.
  inline double row_product(const LO* columns, const double* values, std::size_t length, const double* x)
  {
    double      s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    std::size_t k = 0;
    for (; k + 4 <= length; k += 4)
      {
        s0 += values[k] * x[columns[k]];
        s1 += values[k + 1] * x[columns[k + 1]];
        s2 += values[k + 2] * x[columns[k + 2]];
        s3 += values[k + 3] * x[columns[k + 3]];
      }
    for (; k < length; ++k)
      s0 += values[k] * x[columns[k]];
    return (s0 + s1) + (s2 + s3);
  }
} // namespace multigrid
