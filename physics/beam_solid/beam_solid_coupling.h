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
// Parallel: the solid triangulation is fully distributed (common/distributed_mesh.h); the beam
// mesh is known on every rank and its nodes are split among the ranks by `node_owner`. Each rank
// integrates the parts of the beam elements inside its own cells (a point on a face between two
// ranks' cells is taken by one of them, the owner of the cell with the smallest CellId), every
// element's full coverage is checked over all ranks, and the partial rows of B are summed at the
// owner of their multiplier node: rows of B live once, where their beam node lives. The penalty
// matrix eps B^T k^-1 B is formed there and its rows are sent to the owners of the beam or solid
// DOFs they belong to. kappa and the gaps are beam-sized vectors shared by all ranks (like the
// beam unknowns). Global numbering of the coupled system: beam DOFs [0, n_B) (6 per node), then
// solid DOFs n_B + (deal.II DOF index).
#pragma once

#include "beam_solid/kirchhoff_beam.h"
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
    /// Locates the integration points of this rank's beam elements (those whose first node
    /// `node_owner` assigns to it) in `solid` (Q1 vector FE) and sums the rows of B at their
    /// owners (collective). Throws std::invalid_argument naming `source` when a beam point lies
    /// outside the solid (on every rank).
    BeamSolidCoupling(const BeamMesh& beam, const dealii::DoFHandler<3>& solid, CouplingMethod method,
                      int gauss_points, const std::string& source,
                      const std::function<unsigned int(std::size_t)>& node_owner, MPI_Comm comm);

    /// One row j of B = [D, -M] (per Cartesian component): column ids of the 3 components and a
    /// scalar weight.
    struct Entry
    {
      std::array<GlobalIndex, 3> columns;
      double                     weight;
    };
    /// The rows of B of this rank's beam nodes, by node.
    const std::map<std::size_t, std::vector<Entry>>& rows() const { return rows_; }
    /// kappa_j of every beam node (on every rank).
    const std::vector<double>& kappa() const { return kappa_; }
    /// Solid DOFs the local rows of B read (ghost them in the solid vector).
    const std::vector<GlobalIndex>& solid_dofs() const { return solid_dofs_; }
    /// Number of integration points, on all ranks together.
    std::size_t n_points() const { return n_points_; }

    /// Gap per multiplier node and component, g_j = (D d_B - M d_S)_j, of every beam node on
    /// every rank (collective), from the beam DOFs and the solid displacement (ghosted, incl.
    /// solid_dofs()).
    std::vector<std::array<double, 3>> gaps(const std::vector<double>& beam_dofs,
                                            const dealii::TrilinosWrappers::MPI::Vector& solid) const;

    /// The penalty matrix eps B^T k^-1 B (global numbering of the coupled system), its rows sent
    /// to `row_owner` (collective): returns the rows this rank owns. It is constant, and the
    /// coupling forces are this matrix times the coupled displacement vector.
    RowPieces penalty_matrix(double epsilon, const std::function<unsigned int(GlobalIndex)>& row_owner) const;

  private:
    MPI_Comm                                  comm_;
    unsigned int                              n_beam_dofs_;
    std::map<std::size_t, std::vector<Entry>> rows_;
    std::vector<double>                       kappa_;
    std::vector<GlobalIndex>                  solid_dofs_;
    std::size_t                               n_points_ = 0;
  };
} // namespace physics::beam_solid
