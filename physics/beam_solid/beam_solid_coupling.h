// Penalty coupling of embedded beams to a 3D solid along the beam centrelines (BEAM_SOLID.md,
// Steinbrecher et al. 2020): the constraint u_B(s) - u_S(X(s)) = 0 with a multiplier field
// interpolated linearly between the beam nodes (Phi_j), regularized by a penalty,
//   lambda_j = eps / kappa_j (D d_B - M d_S)_j,   kappa_j = int Phi_j ds,
//   D_jk = int Phi_j H_k ds   (beam DOFs: positions and, through the Hermite functions, tangents),
//   M_jl = int Phi_j N_l(X(s)) ds   (solid DOFs),
// (3 x 3 identity blocks per entry), which adds the coupling forces
//   f_B = D^T lambda,  f_S = -M^T lambda
// and their Jacobian  eps [[D^T k^-1 D, -D^T k^-1 M], [-M^T k^-1 D, M^T k^-1 M]]  (constant:
// the beams are tied to material points of the reference configuration).
//
// Integration: "gpts" (Gauss point to segment) uses each beam element's own Gauss points;
// "mortar" (segment-based) integrates the pieces of each element's centreline inside the solid
// cells (found by bisection on the cell boundary; hexahedra are convex) with Gauss points on every
// piece. Beam points are located with deal.II's GridTools::Cache (R-trees of cell bounding boxes).
//
// Parallel: the solid triangulation is fully distributed (common/distributed_mesh.h), and so are
// the beams (beam_partition.h: every rank stores its own elements and node block). Each rank
// sends its elements to the ranks whose owned cells may hold part of them (the bounding box of
// each rank's owned cells, gathered once: P boxes, not a beam- or mesh-sized array); every rank
// integrates the parts of the elements it received inside its own cells (a point on a face
// between two ranks' cells is taken by one of them, the owner of the cell with the smallest
// CellId); every element's coverage is summed and checked at its owner, and the partial rows of
// B and of kappa are summed at the owner of their multiplier node: rows of B, kappa_j and the
// gap g_j live once, where beam node j lives. The penalty matrix eps B^T k^-1 B is formed there
// and its rows are sent to the owners of the beam or solid DOFs they belong to. Global numbering
// of the coupled system: beam DOFs [0, n_B) (6 per node, beam_partition.h), then solid DOFs
// n_B + (deal.II DOF index).
#pragma once

#include "beam_solid/beam_partition.h"
#include "common/row_exchange.h"

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/trilinos_vector.h>

#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace physics::beam_solid
{
  enum class CouplingMethod
  {
    gpts,
    mortar
  };

  class BeamSolidCoupling
  {
  public:
    /// Locates the integration points of all beam elements in `solid` (Q1 vector FE), each rank
    /// in its own cells, and sums the rows of B and kappa at the owners of their beam nodes
    /// (collective). Throws std::invalid_argument naming `source` when a beam point lies
    /// outside the solid (on every rank, naming the element of smallest global number).
    BeamSolidCoupling(const DistributedBeam& beam, const dealii::DoFHandler<3>& solid, CouplingMethod method,
                      int gauss_points, const std::string& source, MPI_Comm comm);

    /// One row j of B = [D, -M] (per Cartesian component): column ids of the 3 components and a
    /// scalar weight.
    struct Entry
    {
      std::array<GlobalIndex, 3> columns;
      double                     weight;
    };
    /// The rows of B of this rank's beam nodes, by global node.
    const std::map<BeamIndex, std::vector<Entry>>& rows() const { return rows_; }
    /// kappa_j of this rank's beam nodes, by global node.
    const std::map<BeamIndex, double>& kappa() const { return kappa_; }
    /// Solid DOFs the local rows of B read (ghost them in the solid vector).
    const std::vector<GlobalIndex>& solid_dofs() const { return solid_dofs_; }
    /// Beam DOFs the local rows of B read (ghost them in the beam vector): those of the beam
    /// nodes next to this rank's nodes.
    const std::vector<GlobalIndex>& beam_dofs() const { return beam_dofs_; }
    /// Number of integration points, on all ranks together, and the most on one rank (they
    /// lie in the rank's own cells: the partition's balance of the coupling work).
    std::size_t n_points() const { return n_points_; }
    std::size_t max_points_per_rank() const { return max_points_per_rank_; }

    /// Gap per multiplier node and component, g_j = (D d_B - M d_S)_j, of this rank's beam
    /// nodes, from the beam DOFs (ghosted, incl. beam_dofs()) and the solid displacement
    /// (ghosted, incl. solid_dofs()). Not collective: the rows are whole at their owners.
    std::map<BeamIndex, std::array<double, 3>> gaps(const dealii::TrilinosWrappers::MPI::Vector& beam,
                                                    const dealii::TrilinosWrappers::MPI::Vector& solid) const;

    /// The penalty matrix eps B^T k^-1 B (global numbering of the coupled system), its rows sent
    /// to `row_owner` (collective): returns the rows this rank owns. It is constant, and the
    /// coupling forces are this matrix times the coupled displacement vector.
    RowPieces penalty_matrix(double epsilon, const std::function<unsigned int(GlobalIndex)>& row_owner) const;

  private:
    MPI_Comm                                comm_;
    GlobalIndex                             n_beam_dofs_;
    std::map<BeamIndex, std::vector<Entry>> rows_;
    std::map<BeamIndex, double>             kappa_;
    std::vector<GlobalIndex>                solid_dofs_, beam_dofs_;
    std::size_t                             n_points_ = 0, max_points_per_rank_ = 0;
  };
} // namespace physics::beam_solid
