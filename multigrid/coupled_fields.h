// A 3 x 3 block model problem with the layout of the condensed FSI system (FSI.md), built without
// deal.II, for the n x n block preconditioners (fully-coupled-sa-amg(bgs), bgs(amg),
// block-jacobi(amg)) and their tests.
//
// coupled_fields_2d(level): three fields on m x m node grids, m = 8 * 2^level + 1, grid spacing
// scaled out (h = 1 in the stencils):
//   structure  [0,1] x [0,1], 2 DOFs per node: finite-difference Navier-Lame operator
//              -mu Lap(d) - (lambda + mu) grad div(d) (mu = 1, lambda = 1; 5-point Laplacian,
//              4-point cross stencil for the mixed derivatives), clamped at x = 0 (identity rows).
//              Near-nullspace: the rigid-body modes (exact in the interior).
//   fluid      [1,2] x [0,1], 3 DOFs per node (u, v, p): a stabilized Stokes-like saddle point
//              [sigma I + nu Lap, G; G^T, -(eps Lap + delta I)] (sigma = 0.5, nu = 1, central
//              pressure gradient G, eps = 0.5, delta = 0.01): symmetric quasi-definite, so
//              Chebyshev is no use on it and ILU(0) is. Near-nullspace: the 3 constants per component.
//   ale        [1,2] x [0,1], 2 DOFs per node: vector Laplacian, fixed at x = 2 (identity rows).
// Every operator is the principal submatrix of its infinite-grid stencil, so the structure and
// ALE blocks are symmetric positive definite. The fields are coupled through the interface
// (structure column x = 1 <-> fluid and ALE column x = 1, node by node, like the condensed FSI
// system's interface rows):
//   A_FS = -tau (kinematic: the fluid interface velocity follows the structure), tau = 1;
//   A_GS = -1 (the ALE mesh follows the structure);
//   A_SF = -0.5 on the velocities and -0.25 on the pressure (x component): the fluid traction;
//   A_SG = A_FG = -0.1 (shape-derivative-like terms).
// With `lower_triangular` the three upper couplings (A_SF, A_SG, A_FG) are dropped: one block
// Gauss-Seidel sweep with exact block solves is then an exact solve.
// The right-hand side is 1 in every row that is not an identity (Dirichlet) row.
#pragma once

#include "block_system.h"

namespace multigrid
{
  struct CoupledFieldsOptions
  {
    int  level            = 0;
    bool lower_triangular = false;
  };

  BlockSystem coupled_fields_2d(RCP<const Comm> comm, const CoupledFieldsOptions& options);
} // namespace multigrid
