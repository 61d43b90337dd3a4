// The explicit Schur complement S = C - s B2 Â B1^T of a 2 x 2 block matrix [A B1^T; B2 C] with a
// sparse Â ≈ A^-1 (diagonal or SPAI), shared by CheapSIMPLE (s = 1) and the Schur-complement
// factory of the saddle-point AMG templates (s = 1 / omega: the SIMPLE smoothers of the contact
// presets, and the monolithic beam/solid AMG).
//
// Memory, not flops, decides how it is formed. Measured on the beam/solid fibre block, 8 ranks,
// 155 k DOFs, where S is the largest matrix of the preconditioner (3.7 M entries on the rank with
// the most):
//  - Order. Each product imports the rows of its right factor that the left factor's columns name
//    on other ranks. The beam nodes are distributed in fibre order and the solid by METIS, so
//    nearly all of those rows are remote; (B2 Â) B1^T imports rows of Â (66 entries per beam row)
//    where B2 (Â B1^T) imported rows of Â B1^T (124): the largest peak per rank fell from 694 to
//    660 MB.
//  - The sum. Xpetra's TwoMatrixAdd (Tpetra's add) merges rows in global column ids before it
//    builds the column map; here the column map is made first (from the two column maps) and S
//    is written straight into its local indices, exactly sized: the largest peak per rank fell
//    from 636 to 560 MB on those 8 ranks, from 541 to 490 MB on 2 ranks (41 k DOFs).
#pragma once

#include "types.h"

namespace multigrid
{
  /// S = C - scale B2 Â B1^T, fill complete, with C's domain and range maps and its fixed block
  /// size. C may be null (a coarse level whose all-zero C block Xpetra does not store): then
  /// S = -scale B2 Â B1^T.
  RCP<Matrix> explicit_schur_complement(const RCP<Matrix>& C, const Matrix& B2, const Matrix& A_inverse,
                                        const Matrix& B1t, double scale);

  /// C + beta P of two fill-complete matrices with the same row, domain and range maps, in C's
  /// row map with a column map that holds the columns of both (owned ones first, as Tpetra makes
  /// it), each row sorted and merged.
  RCP<Matrix> add_matrices(const Matrix& C, double beta, const Matrix& P);
} // namespace multigrid
