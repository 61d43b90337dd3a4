#include "beam_solid/beam_solid_coupling.h"

#include <deal.II/base/geometry_info.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/grid_tools_cache.h>

#include <set>
#include <sstream>
#include <stdexcept>

namespace physics::beam_solid
{
  using namespace dealii;

  namespace
  {
    using CellIterator = typename Triangulation<3>::active_cell_iterator;

    struct IntegrationPoint
    {
      std::size_t  element;
      double       xi, ds; ///< element coordinate, weight in reference arc length
      CellIterator cell;
      Point<3>     unit; ///< in the solid cell's reference coordinates
    };

    Point<3> position(const BeamMesh& beam, std::size_t e, double xi)
    {
      const Point<3>& a = beam.nodes[beam.elements[e][0]];
      const Point<3>& b = beam.nodes[beam.elements[e][1]];
      return a + (b - a) * (0.5 * (xi + 1)); // straight reference elements
    }

    /// The cell containing p (and p's unit coordinates); throws with the beam point's location.
    std::pair<CellIterator, Point<3>> locate(const GridTools::Cache<3>& cache, const Point<3>& p, std::size_t e,
                                             const std::string& source)
    {
      std::pair<CellIterator, Point<3>> found;
      try
        {
          found = GridTools::find_active_cell_around_point(cache, p);
        }
      catch (...)
        {
          found.first = CellIterator();
        }
      if (found.first.state() != IteratorState::valid)
        {
          std::ostringstream where;
          where << p;
          throw std::invalid_argument(source + ": beam element " + std::to_string(e) + " has a point (" + where.str() +
                                      ") outside the solid");
        }
      return found;
    }

    bool inside(const Mapping<3>& mapping, const CellIterator& cell, const Point<3>& p)
    {
      try
        {
          return GeometryInfo<3>::is_inside_unit_cell(mapping.transform_real_to_unit_cell(cell, p), 1e-10);
        }
      catch (const typename Mapping<3>::ExcTransformationFailed&)
        {
          return false;
        }
    }

    /// Segment-based: split [-1, 1] where the centreline leaves a cell (bisection on xi; hexahedra
    /// are convex, so a straight piece leaves each cell once), Gauss points on every piece.
    void mortar_points(const BeamMesh& beam, std::size_t e, const GridTools::Cache<3>& cache,
                       const QGauss<1>& gauss, const std::string& source, std::vector<IntegrationPoint>& points)
    {
      const Mapping<3>& mapping = cache.get_mapping();
      const double      l       = beam.element_length(e);
      double            xi_a    = -1.0;
      for (int piece = 0; xi_a < 1.0 - 1e-12; ++piece)
        {
          if (piece > 10000)
            throw std::runtime_error(source + ": beam element " + std::to_string(e) + " crosses too many cells");
          const CellIterator cell = locate(cache, position(beam, e, std::min(xi_a + 1e-8, 1.0)), e, source).first;
          double             xi_b = 1.0;
          if (!inside(mapping, cell, position(beam, e, 1.0)))
            {
              double lo = std::min(xi_a + 1e-8, 1.0), hi = 1.0;
              for (int k = 0; k < 60 && hi - lo > 1e-14; ++k)
                {
                  const double mid = 0.5 * (lo + hi);
                  (inside(mapping, cell, position(beam, e, mid)) ? lo : hi) = mid;
                }
              xi_b = lo;
            }
          for (unsigned int q = 0; q < gauss.size(); ++q)
            {
              const double   xi = xi_a + (xi_b - xi_a) * gauss.point(q)[0];
              const Point<3> p  = position(beam, e, xi);
              points.push_back({e, xi, gauss.weight(q) * 0.5 * (xi_b - xi_a) * l, cell,
                                mapping.transform_real_to_unit_cell(cell, p)});
            }
          xi_a = xi_b;
        }
    }
  } // namespace

  BeamSolidCoupling::BeamSolidCoupling(const BeamMesh& beam, const DoFHandler<3>& solid, CouplingMethod method,
                                       int gauss_points, const std::string& source,
                                       const std::function<unsigned int(std::size_t)>& node_owner, MPI_Comm comm)
      : comm_(comm)
      , n_beam_dofs_(beam.n_dofs())
  {
    const unsigned int        rank = Utilities::MPI::this_mpi_process(comm);
    const auto&               tria = solid.get_triangulation();
    const GridTools::Cache<3> cache(tria, StaticMappingQ1<3>::mapping);
    const QGauss<1>           gauss(gauss_points); // on [0, 1]

    // This rank's elements: those whose first node it owns.
    std::vector<IntegrationPoint> points;
    std::string                   error;
    try
      {
        for (std::size_t e = 0; e < beam.elements.size(); ++e)
          {
            if (node_owner(beam.elements[e][0]) != rank)
              continue;
            if (method == CouplingMethod::mortar)
              mortar_points(beam, e, cache, gauss, source, points);
            else
              for (unsigned int q = 0; q < gauss.size(); ++q)
                {
                  const double xi    = 2 * gauss.point(q)[0] - 1;
                  const auto   found = locate(cache, position(beam, e, xi), e, source);
                  points.push_back({e, xi, gauss.weight(q) * beam.element_length(e), found.first, found.second});
                }
          }
      }
    catch (const std::exception& e)
      {
        error = e.what();
      }
    throw_if_any_rank_failed(error, comm);
    n_points_ = Utilities::MPI::sum(points.size(), comm);

    // Partial rows j of B = [D, -M] from this rank's points, row j -> (x-component column ->
    // weight); the y and z columns follow the x column (beam: 6 DOFs per node, solid: node-major).
    RowPieces partial;
    kappa_.assign(beam.nodes.size(), 0.0);
    for (const auto& point : points)
      {
        const auto&  nodes = beam.elements[point.element];
        const double l     = beam.element_length(point.element);
        const auto   h     = centreline_weights(point.xi, l);
        const typename DoFHandler<3>::active_cell_iterator cell(&tria, point.cell->level(), point.cell->index(), &solid);
        for (int a = 0; a < 2; ++a)
          {
            const int    j   = nodes[a];
            const double phi = a == 0 ? 0.5 * (1 - point.xi) : 0.5 * (1 + point.xi);
            kappa_[j] += phi * point.ds;
            // D: beam position / tangent unknowns of both element nodes.
            for (int k = 0; k < 4; ++k)
              partial[j][6 * static_cast<GlobalIndex>(nodes[k / 2]) + 3 * (k % 2)] += phi * h[k] * point.ds;
            // -M: solid vertex unknowns of the cell, trilinear shape functions.
            for (unsigned int v = 0; v < GeometryInfo<3>::vertices_per_cell; ++v)
              partial[j][n_beam_dofs_ + cell->vertex_dof_index(v, 0)] -=
                  phi * GeometryInfo<3>::d_linear_shape_function(point.unit, v) * point.ds;
          }
      }
    Utilities::MPI::sum(kappa_, comm, kappa_);

    // Whole rows at the owners of their multiplier nodes.
    std::set<GlobalIndex> solid_dofs;
    for (const auto& [j, row] : send_rows_to_owners(partial, [&](GlobalIndex n) { return node_owner(n); }, comm))
      {
        auto& entries = rows_[j];
        for (const auto& [column, weight] : row)
          {
            entries.push_back({{{column, column + 1, column + 2}}, weight});
            if (column >= n_beam_dofs_)
              for (unsigned int c = 0; c < 3; ++c)
                solid_dofs.insert(column - n_beam_dofs_ + c);
          }
      }
    solid_dofs_.assign(solid_dofs.begin(), solid_dofs.end());
  }

  std::vector<std::array<double, 3>> BeamSolidCoupling::gaps(const std::vector<double>& beam_dofs,
                                                             const TrilinosWrappers::MPI::Vector& solid) const
  {
    std::vector<double> g(3 * kappa_.size(), 0.0);
    for (const auto& [j, row] : rows_)
      for (const auto& entry : row)
        for (unsigned int c = 0; c < 3; ++c)
          {
            const GlobalIndex col   = entry.columns[c];
            const double      value = col < n_beam_dofs_ ? beam_dofs[col] : solid[col - n_beam_dofs_];
            g[3 * j + c] += entry.weight * value;
          }
    Utilities::MPI::sum(g, comm_, g);
    std::vector<std::array<double, 3>> result(kappa_.size());
    for (std::size_t j = 0; j < result.size(); ++j)
      result[j] = {{g[3 * j], g[3 * j + 1], g[3 * j + 2]}};
    return result;
  }

  RowPieces BeamSolidCoupling::penalty_matrix(double epsilon,
                                              const std::function<unsigned int(GlobalIndex)>& row_owner) const
  {
    // Node j contributes eps / kappa_j (B_j)^T B_j: every pair of its entries, per component.
    RowPieces matrix;
    for (const auto& [j, row] : rows_)
      {
        if (kappa_[j] <= 0)
          continue;
        const double scale = epsilon / kappa_[j];
        for (const auto& a : row)
          for (unsigned int c = 0; c < 3; ++c)
            {
              auto& matrix_row = matrix[a.columns[c]];
              for (const auto& b : row)
                matrix_row[b.columns[c]] += scale * a.weight * b.weight;
            }
      }
    return send_rows_to_owners(matrix, row_owner, comm_);
  }
} // namespace physics::beam_solid
