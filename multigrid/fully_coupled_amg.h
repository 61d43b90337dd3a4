// Fully coupled SA-AMG for n x n block systems with a block Gauss-Seidel level smoother: the
// seeds' FSI preconditioner "AMG(BGS)" (Gee, Kuettler, Wall 2011; FSI.md), preset
// `fully-coupled-sa-amg(bgs)`, kind "fully-coupled-amg".
//
// One monolithic hierarchy for the whole n x n operator:
//   1. aggregation per field on its own diagonal block A_kk (so no aggregate spans two fields),
//      nodes from the block's strided map (its DOFs per node);
//   2. a tentative prolongator per field from that field's near-nullspace (QR per aggregate:
//      Ptent_k Bc_k = B_k), smoothed on A_kk (SA: P_k = (I - omega/lambda D_kk^-1 A_kk) Ptent_k);
//   3. P = diag(P_0, ..., P_n-1), R = P^T, and the Galerkin product R A P of the whole n x n
//      operator, couplings included (so every level is again an n x n block system);
//   4. level smoother: `smoother: sweeps` x block Gauss-Seidel with damping `smoother: damping`,
//      one sub-smoother per block (Ifpack2 through MueLu's TrilinosSmoother, or SuperLU);
//   5. coarse solve: the project's SuperLU on the merged coarse operator.
// MueLu 13.2's blocked factories do the transfers (SubBlockAFactory, UncoupledAggregationFactory,
// TentativePFactory, SaPFactory, CoarseMapFactory/BlockedCoarseMapFactory, BlockedPFactory,
// GenericRFactory). The project's own: the Galerkin product (BlockedGalerkinFactory,
// coupled_prolongator.h: each block R_ii A_ij P_jj with A_ij first multiplied by the sparser
// transfer: 0.83-0.93x the SA set-up of MueLu's BlockedRAPFactory on the tube, which forms A P
// first), the level smoother (block_gauss_seidel_smoother.h), the fluid's ILU(0) and the coarse
// solver (SuperLUDirectSolver, project_factories.h: 13.2's BlockedDirectSolver ignores its
// parameters and uses Amesos2 KLU2, which has no SuperLU here and is inexact on several ranks).
// The factory list is written here for the system's number of blocks (an XML template would fix
// n); solve_block_system --print-xml prints it.
//
// Preset parameters: "max levels", "coarse: max size", "aggregation: min agg size",
// "aggregation: ordering" (the order of MueLu's uncoupled aggregation: natural | graph | random),
// "prolongator" (smoothed | tentative; per block in the optional sublist "block prolongators",
// NAME = smoothed | tentative), "sa: damping factor", "smoother: sweeps",
// "smoother: damping", "smoother: max growth" (see check_level_smoother), and the sublist
// "block smoothers" with one sublist per block name or "default": "type" (an Ifpack2 type of
// MueLu's TrilinosSmoother: CHEBYSHEV, RILUK, RELAXATION, ...; ILU(0) or SGS for the project's
// (ilu0_smoother.h, gauss_seidel_smoother.h); or SuperLU for an exact block solve) and the sublist
// "ParameterList" (that smoother's parameters); and the optional sublist "block aggregates",
// FOLLOWER = LEADER (block names, the leader before the follower; "own": the block aggregates on
// its own diagonal block, the default): the follower's nodes join the aggregates of the leader's
// nodes at the same positions (node_interface_aggregation.h), so both fields coarsen onto one
// coarse mesh - the FSI's ALE field lives on the fluid mesh; the follower's nodes without a
// leader node at their position are aggregated on its own graph, where they grow the copied
// aggregates - the FSI fluid shares only the interface with the structure ("fluid = structure":
// one coarse interface). Not with "repartition/enable" (the rebalancing moves the node mapping
// of the contact lists' two blocks only).
#pragma once

#include "block_system.h"
#include "hierarchy_utils.h"
#include "presets.h"

#include <Teuchos_ParameterList.hpp>

#include <map>
#include <string>
#include <vector>

namespace multigrid
{
  /// Checks the preset against the system before the setup: every block that will be coarsened
  /// has at least `aggregation: min agg size` nodes. Throws InputError (one line) otherwise.
  void check_fully_coupled(const Preset& preset, const BlockSystem& system);

  /// MueLu's factory list ("Factories" and "Hierarchy") of the preset for this system's blocks.
  Teuchos::ParameterList fully_coupled_muelu_list(const Preset& preset, const BlockSystem& system);

  /// Level-0 user data of the blocks that copy another block's aggregates (preset sublist
  /// "block aggregates"): name -> (local follower node -> local leader node at the same position,
  /// or no_primal_node).
  using LeaderNodeMaps = std::map<std::string, std::map<LO, LO>>;

  /// The node maps of every block that follows another block's aggregates, matched by node
  /// positions on each rank (nodes without a partner on their rank are aggregated on the
  /// follower's own graph);
  /// a line per such block goes to `notes`. Throws InputError when no node of a block matches.
  LeaderNodeMaps follower_node_maps(const Preset& preset, const BlockSystem& system,
                                    std::vector<std::string>& notes);

  /// The level smoother's residual growth on the fine level: ||A x_5|| / ||A x_0|| after five
  /// applications to A x = 0 from a random x_0 (< 1: it contracts). Throws InputError when it
  /// exceeds the preset's "smoother: max growth" (the smoother diverges, the multigrid cycle
  /// would too); below that the factor is reported and GMRES runs (at most its iteration limit).
  double check_level_smoother(Hierarchy& H, const BlockSystem& system, const Preset& preset);
} // namespace multigrid
