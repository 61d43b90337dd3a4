// Saddle-point model problems built without deal.II, for the built-in example of
// solve_block_system and for tests of the block-AMG module.
//
// tied_blocks_2d(level): two plane-strain linear elastic bodies, body 1 = [0,1] x [0,0.5] (master,
// clamped at y = 0, 2m x m bilinear elements) and body 2 = [0,1] x [0.5,1] (slave, 3m x 3m/2
// elements: non-matching at the interface y = 0.5), m = 8 * 2^level. The top face of body 2 is
// pushed by a prescribed displacement (0.01, -0.02), the load of the two-block contact benchmark;
// the bodies are tied along the interface by Lagrange multipliers on the slave side
// (segment-based mortar integration; Dirichlet rows eliminated symmetrically):
//
//     [ K1    0    -M^T ] [u1]   [0]
//     [ 0     K2    D^T ] [u2] = [g]        D_jk = int Phi_j N_k^(2),  M_jl = int Phi_j N_l^(1)
//     [ -M    D     0   ] [l ]   [0]
//
// Dual multiplier shape functions (Phi_1 = 2 N_1 - N_2 on a segment) make D diagonal; standard
// ones (Phi = N) give a surface mass matrix. The number of DOFs grows 4x per level.
#pragma once

#include "block_system.h"

namespace multigrid
{
  struct TiedBlocksOptions
  {
    int    level            = 0;
    bool   dual_multipliers = true;
    double youngs_modulus   = 1.0;
    double poisson_ratio    = 0.3;
  };

  BlockSystem tied_blocks_2d(RCP<const Comm> comm, const TiedBlocksOptions& options);

  /// "tied-blocks-2d:LEVEL" or "coupled-fields-2d:LEVEL" (coupled_fields.h) -> the system; throws
  /// InputError for an unknown name.
  BlockSystem builtin_system(const std::string& spec, RCP<const Comm> comm);
} // namespace multigrid
