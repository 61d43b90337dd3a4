// Sparse approximations Â ≈ A^-1, for what MueLu 13.2 lacks (no InverseApproximationFactory):
// the Schur complement S = C - B Â^-1 B^T of the beam/solid preset `schur-sa-amg(spai)` (seed
// 001) and the SPAI smoother x <- x - Â (A x - b).
//
//   diagonal           Â = diag(A)^-1
//   row-sum            Â = diag(1 / sum_j a_ij)                 (row-sum lumping, as of a mass
//                                                              matrix; singular for a stiffness
//                                                              matrix, whose free rows sum to 0)
//   absolute-row-sum   Â = diag(sign(a_ii) / sum_j |a_ij|)      (MueLu's "lumping", SIMPLEC's Â;
//   (alias lumping)                                            |Â_ii| <= 1 / |a_ii|)
//   spai               Â = argmin ||A Â - I||_F over a prescribed sparsity pattern P
//
// The Frobenius norm decouples into one small least-squares problem per column k of Â:
//   min || A(I_k, J_k) m_k - e_k(I_k) ||_2,
// J_k = the pattern of column k (the rows of P in column k), I_k = the rows of A that have a
// nonzero in one of the columns J_k (all other rows of A(:, J_k) vanish). Columns of A are rows of
// A^T, so the algorithm runs row-wise on A^T (rows of A^T in J_k imported from their owners) and
// produces Â^T row by row; Â is its transpose. P is the pattern of A^k (k = pattern power,
// 1 to 4), of A^T's rows, with entries dropped where |p_kj| < drop_tolerance * max_j |p_kj| (the
// diagonal is always kept). For symmetric A the pattern is symmetric, and Â is nonsymmetric in
// general; a larger pattern never increases ||A Â - I||_F (the minimization space grows).
#pragma once

#include "types.h"

#include <Teuchos_ParameterList.hpp>
#include <Tpetra_CrsMatrix_fwd.hpp>
#include <Tpetra_MultiVector_fwd.hpp>

#include <string>

namespace multigrid
{
  using TpetraMatrix      = Tpetra::CrsMatrix<SC, LO, GO, NO>;
  using TpetraMultiVector = Tpetra::MultiVector<SC, LO, GO, NO>;

  struct InverseApproximationOptions
  {
    std::string type           = "spai"; ///< diagonal | row-sum | absolute-row-sum (lumping) | spai
    int         pattern_power  = 1;      ///< spai: pattern of A^k, k = 1 ... 4
    double      drop_tolerance = 0.0;    ///< spai: relative to the largest entry of the pattern row
  };

  /// Options from a parameter list: the type under `type_key` (default `default_type`), then
  /// "spai: pattern power" and "spai: drop tolerance" (defaults above).
  InverseApproximationOptions inverse_approximation_options(const Teuchos::ParameterList& list,
                                                            const std::string& type_key,
                                                            const std::string& default_type);

  /// Â for A (square, fill-complete, row map = range map). Throws InputError for an unknown type,
  /// a pattern power outside 1 ... 4, a negative drop tolerance, or a zero diagonal or zero (lumped)
  /// row sum.
  Teuchos::RCP<TpetraMatrix> approximate_inverse(const TpetraMatrix& A, const InverseApproximationOptions& options);
  /// The same on an Xpetra matrix (Tpetra underneath).
  RCP<Matrix> approximate_inverse(const Matrix& A, const InverseApproximationOptions& options);

  /// ||A Â - I||_F (global).
  double inverse_residual_norm(const TpetraMatrix& A, const TpetraMatrix& A_inverse);

  /// `sweeps` steps of x <- x + damping Â (b - A x).
  void spai_smooth(const TpetraMatrix& A, const TpetraMatrix& A_inverse, const TpetraMultiVector& b,
                   TpetraMultiVector& x, int sweeps, double damping = 1.0);
} // namespace multigrid
