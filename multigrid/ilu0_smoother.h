// Incomplete LU factorization without fill, ILU(0): the fluid block's sub-smoother of the fully
// coupled FSI AMG (seed 001), type "ILU(0)" in a preset's "block smoothers".
//
// A ~ L U, where the unit lower triangle L and the upper triangle U have exactly the sparsity of
// A's lower and upper parts: Gaussian elimination row by row (IKJ order) that drops every entry
// outside A's pattern,
//     for i = 0 .. n-1:  for k < i with a_ik != 0:   l_ik = a_ik / u_kk
//                                                   a_ij -= l_ik u_kj   (j > k, a_ij in the pattern)
//                        u_ij = a_ij (j >= i).
// One application solves L U x = b by a forward and a backward substitution. As with Ifpack2's
// RILUK under MueLu, the factorization is rank-local: entries that couple to another rank's rows
// are left out (block Jacobi between the ranks), and the optional diagonal perturbation
// a_ii -> relative a_ii + sign(a_ii) absolute uses Ifpack2's parameter names.
//
// Why not Ifpack2's RILUK (level of fill 0), which computes the same factors: its triangular solves
// (Kokkos Kernels 13.2's sequential trsv) update x_i through the multivector inside the loop over
// the row, so that every product waits for the store of the one before; on the 3D tube's fluid
// block (35 k rows, 75 k DOFs in all) they were 44 % of the fully coupled preset's solve. Here each
// row's sum is kept in four independent registers, and L and U lie in separate arrays, so that a
// substitution streams through its own triangle only.
#pragma once

#include "kernel_smoother.h"
#include "types.h"

#include <cstddef>
#include <memory>
#include <vector>

namespace multigrid
{
  struct Ilu0Thresholds
  {
    double absolute = 0.0; ///< "fact: absolute threshold"
    double relative = 1.0; ///< "fact: relative threshold"
  };

  /// ILU(0) of a matrix's rank-local block (rows and columns this rank owns).
  class Ilu0Factors
  {
  public:
    using Settings                          = Ilu0Thresholds;
    static constexpr const char* const name = "ILU(0) (project)";

    /// Factorizes the rank-local block of A (an Xpetra matrix on Tpetra; not a blocked one).
    /// Throws InputError naming the local row if a pivot is zero or not finite.
    explicit Ilu0Factors(const RCP<const Matrix>& A, const Ilu0Thresholds& thresholds = {});

    /// x = (L U)^-1 b for one column of local values (x and b may be the same array).
    void solve(const double* b, double* x) const;
    /// X = (L U)^-1 B from a zero start, else X += (L U)^-1 (B - A X).
    void apply(MultiVector& X, const MultiVector& B, bool zero_start) const;

    std::size_t rows() const { return inverse_diagonal_.size(); }
    /// Stored entries: strict L, strict U and the diagonal.
    std::size_t nonzeros() const { return lower_.columns.size() + upper_.columns.size() + rows(); }

  private:
    /// One strict triangle in compressed rows.
    struct Triangle
    {
      std::vector<std::size_t> offsets;
      std::vector<LO>          columns;
      std::vector<double>      values;
    };
    RCP<const Matrix>   A_;                ///< for the residual of a given start
    Triangle            lower_;            ///< l_ik, k < i (unit diagonal not stored)
    Triangle            upper_;            ///< u_ij, j > i
    std::vector<double> inverse_diagonal_; ///< 1 / u_ii
  };

  /// ILU(0) as a MueLu smoother: x += (L U)^-1 (b - A x), from a zero start x = (L U)^-1 b.
  /// In the XML: factory "Ilu0Smoother" with an optional sublist "ParameterList" holding
  /// "fact: absolute threshold" and "fact: relative threshold".
  using Ilu0Smoother = KernelSmoother<Ilu0Factors>;

  /// The thresholds in the sublist `sublist` of an "ILU(0)" smoother's `settings` (none there:
  /// Ifpack2's defaults). The sublist may also hold RILUK's "fact: iluk level-of-fill" = 0;
  /// InputError (naming `where`) for any other parameter, for a negative absolute or a
  /// non-positive relative threshold.
  Ilu0Thresholds ilu0_thresholds(const Teuchos::ParameterList& settings, const std::string& sublist,
                                 const std::string& where);
} // namespace multigrid
