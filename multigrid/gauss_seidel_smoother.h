// Symmetric Gauss-Seidel, the level smoother of the contact presets (the predictor inside SIMPLE,
// the corrector on the Schur complement, CheapSIMPLE's SA-AMG on the displacements), type "SGS"
// in a preset's smoother lists and factory "GaussSeidelSmoother" in MueLu XML.
//
// One symmetric sweep on A x = b is a forward sweep over the rows followed by a backward one,
//     x_i <- x_i + omega / a_ii (b_i - sum_j a_ij x_j),
// each row using the newest values of the rows before it. Between ranks it is Ifpack2's Relaxation
// exactly: every sweep starts from the other ranks' x of the sweep before (imported once per
// sweep, none in the first sweep from a zero start), so that across ranks it is block Jacobi.
// The parameters are Ifpack2's names: "relaxation: sweeps", "relaxation: damping factor" and
// "relaxation: type" = "Symmetric Gauss-Seidel".
//
// Why not Ifpack2's "Symmetric Gauss-Seidel" through MueLu's TrilinosSmoother: its loop keeps one
// running sum per row (row_product.h); on the 66 k DOF 3D contact system it was 87 % of
// fully-coupled-sa-amg(simple)'s solve. This one computes the same sweeps to round-off.
#pragma once

#include "kernel_smoother.h"
#include "types.h"

#include <Tpetra_Import_fwd.hpp>
#include <Tpetra_MultiVector_fwd.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace Teuchos
{
  class ParameterList;
}

namespace multigrid
{
  struct GaussSeidelSettings
  {
    int    sweeps  = 1;   ///< "relaxation: sweeps"
    double damping = 1.0; ///< "relaxation: damping factor" (omega)
  };

  /// The settings in the sublist `sublist` of `settings` (none there: one sweep, no damping).
  /// InputError (naming `where`) for another parameter, another relaxation type, sweeps < 1 or a
  /// damping factor that is zero or not finite.
  GaussSeidelSettings gauss_seidel_settings(const Teuchos::ParameterList& settings,
                                            const std::string& sublist, const std::string& where);

  /// Symmetric Gauss-Seidel sweeps with the rank-local rows of one matrix.
  class SymmetricGaussSeidel
  {
  public:
    using Settings                          = GaussSeidelSettings;
    static constexpr const char* const name = "symmetric Gauss-Seidel (project)";

    /// A: an Xpetra matrix on Tpetra (not a blocked one) whose row, range and domain maps are the
    /// same. Throws InputError naming the local row if a diagonal entry is zero, missing or not
    /// finite.
    SymmetricGaussSeidel(const RCP<const Matrix>& A, const GaussSeidelSettings& settings);

    /// `sweeps` symmetric sweeps on A X = B (X and B in A's row map); from X = 0 where
    /// `zero_start`, else from X's values.
    void apply(MultiVector& X, const MultiVector& B, bool zero_start) const;

    /// Stored entries of A on this rank and its diagonal.
    std::size_t nonzeros() const { return offsets_ == nullptr ? 0 : offsets_[rows_] + rows_; }

  private:
    using TpetraMultiVector = Tpetra::MultiVector<SC, LO, GO, NO>;

    /// One sweep, forward or backward, on local column-map values x; `from_zero`: the first
    /// forward sweep from x = 0, over each row's strictly lower part only (where A's rows allow).
    void sweep(const double* b, double* x, bool forward, bool from_zero) const;

    RCP<const Matrix>        A_; ///< owns the local rows below
    GaussSeidelSettings      settings_;
    std::size_t              rows_    = 0;
    const std::size_t*       offsets_ = nullptr; ///< A's local rows (column-map indices)
    const LO*                columns_ = nullptr;
    const double*            values_  = nullptr;
    std::vector<double>      scaled_inverse_diagonal_; ///< omega / a_ii
    std::vector<std::size_t> lower_ends_; ///< end of row i's entries with column < i (empty: unsorted rows)
    RCP<const Tpetra::Import<LO, GO, NO>> importer_;  ///< domain -> column map; null on one rank
    mutable RCP<TpetraMultiVector>        x_columns_; ///< X on the column map (with an importer)
  };

  /// The symmetric Gauss-Seidel smoother in MueLu. Factory "GaussSeidelSmoother" with an optional
  /// sublist "ParameterList" (gauss_seidel_settings).
  using GaussSeidelSmoother = KernelSmoother<SymmetricGaussSeidel>;
} // namespace multigrid
