#include "beam_solid/beam_solid_coupling.h"

#include <deal.II/base/geometry_info.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/grid_tools_cache.h>
#include <deal.II/numerics/rtree.h>

#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>

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

    /// Of the locally known cells containing p (within deal.II's unit-cell tolerance), the one
    /// with the smallest CellId, or an invalid iterator if this rank knows none. The owner of
    /// that cell knows every cell containing p (they all touch p, so they are its neighbours or
    /// ghosts), hence exactly one rank finds its own cell here: a point on a face shared by two
    /// ranks' cells is integrated once.
    CellIterator agreed_cell(const GridTools::Cache<3>& cache, const Point<3>& p)
    {
      std::pair<CellIterator, Point<3>> first;
      try
        {
          first = GridTools::find_active_cell_around_point(cache, p);
        }
      catch (...)
        {
          return CellIterator();
        }
      if (first.first.state() != IteratorState::valid || first.first->is_artificial())
        return CellIterator();
      CellIterator best = first.first;
      for (const auto& [cell, unit] : GridTools::find_all_active_cells_around_point(
               cache.get_mapping(), cache.get_triangulation(), p, 1e-10, first))
        if (!cell->is_artificial() && cell->id() < best->id())
          best = cell;
      return best;
    }

    /// Which unit-cell coordinates of the point at xi lie on a face of `cell` (within 1e-8): a
    /// centreline along a face stays on it, and only there may the crossing test allow round-off.
    std::array<bool, 3> on_faces(const BeamMesh& beam, std::size_t e, const Mapping<3>& mapping,
                                 const CellIterator& cell, double xi)
    {
      const Point<3>      u = mapping.transform_real_to_unit_cell(cell, position(beam, e, xi));
      std::array<bool, 3> on{};
      for (unsigned int d = 0; d < 3; ++d)
        on[d] = std::abs(u[d]) < 1e-8 || std::abs(u[d] - 1) < 1e-8;
      return on;
    }

    /// Inside the cell, with deal.II's tolerance of 1e-10 in the unit-cell coordinates marked
    /// `tolerant` and none in the others. The crossings of a centreline are found with no
    /// tolerance across the faces it crosses, so that two neighbouring cells find the same
    /// crossing point (to round-off) and the pieces of an element add up to its length; only
    /// along the faces it lies on is round-off allowed.
    bool inside(const Mapping<3>& mapping, const CellIterator& cell, const Point<3>& p,
                const std::array<bool, 3>& tolerant = {{true, true, true}})
    {
      try
        {
          const Point<3> u = mapping.transform_real_to_unit_cell(cell, p);
          for (unsigned int d = 0; d < 3; ++d)
            {
              const double tolerance = tolerant[d] ? 1e-10 : 0.0;
              if (u[d] < -tolerance || u[d] > 1 + tolerance)
                return false;
            }
          return true;
        }
      catch (const typename Mapping<3>::ExcTransformationFailed&)
        {
          return false;
        }
    }

    /// Bisection for where a straight centreline crosses the boundary of a (convex) hexahedron:
    /// `in` inside, `out` outside; returns the crossing parameter (to ~1e-14).
    double crossing(const BeamMesh& beam, std::size_t e, const Mapping<3>& mapping, const CellIterator& cell,
                    const std::array<bool, 3>& on, double in, double out)
    {
      for (int k = 0; k < 60 && std::abs(out - in) > 1e-15; ++k)
        {
          const double mid = 0.5 * (in + out);
          (inside(mapping, cell, position(beam, e, mid), on) ? in : out) = mid;
        }
      return 0.5 * (in + out);
    }

    /// The part [a, b] of element e's centreline inside `cell` (hexahedra are convex, so it is one
    /// interval); false if the centreline misses the cell. A point inside is searched among
    /// samples of the part within the cell's bounding box, then both ends are found by bisection.
    bool piece_in_cell(const BeamMesh& beam, std::size_t e, const Mapping<3>& mapping, const CellIterator& cell,
                       const BoundingBox<3>& box, double& a, double& b)
    {
      // Slab clipping of the straight segment against the bounding box.
      const Point<3> p0 = position(beam, e, -1.0), p1 = position(beam, e, 1.0);
      double         t0 = -1.0, t1 = 1.0;
      for (unsigned int d = 0; d < 3; ++d)
        {
          const double dx = 0.5 * (p1[d] - p0[d]);
          const double lo = box.get_boundary_points().first[d], hi = box.get_boundary_points().second[d];
          if (std::abs(dx) < 1e-300)
            {
              if (p0[d] < lo || p0[d] > hi)
                return false;
              continue;
            }
          double s0 = -1.0 + (lo - p0[d]) / dx, s1 = -1.0 + (hi - p0[d]) / dx;
          if (s0 > s1)
            std::swap(s0, s1);
          t0 = std::max(t0, s0);
          t1 = std::min(t1, s1);
        }
      if (t0 > t1)
        return false;
      constexpr int n_samples = 9;
      for (int k = 0; k < n_samples; ++k)
        {
          const double m = t0 + (t1 - t0) * (k + 0.5) / n_samples;
          if (!inside(mapping, cell, position(beam, e, m)))
            continue;
          const auto on = on_faces(beam, e, mapping, cell, m);
          a = inside(mapping, cell, position(beam, e, -1.0), on) ? -1.0
                                                                         : crossing(beam, e, mapping, cell, on, m, -1.0);
          b = inside(mapping, cell, position(beam, e, 1.0), on) ? 1.0
                                                                        : crossing(beam, e, mapping, cell, on, m, 1.0);
          return b > a;
        }
      return false;
    }

    /// Segment-based ("mortar") integration points of element e in this rank's cells: the pieces
    /// of the centreline inside each locally owned cell (candidates from the R-tree of their
    /// bounding boxes), each kept by the rank whose cell agreed_cell() names at its midpoint
    /// (a centreline along a face between cells is integrated once), with Gauss points on every
    /// piece. Returns the kept pieces' total length in xi.
    double mortar_points(const BeamMesh& beam, std::size_t e, const GridTools::Cache<3>& cache,
                         const QGauss<1>& gauss, std::vector<IntegrationPoint>& points,
                         std::vector<std::pair<double, double>>& pieces)
    {
      const Mapping<3>& mapping = cache.get_mapping();
      const double      l       = beam.element_length(e);
      const Point<3>    p0 = position(beam, e, -1.0), p1 = position(beam, e, 1.0);
      BoundingBox<3>    element_box(std::make_pair(p0, p0));
      element_box.merge_with(BoundingBox<3>(std::make_pair(p1, p1)));
      std::vector<std::pair<BoundingBox<3>, CellIterator>> candidates;
      cache.get_locally_owned_cell_bounding_boxes_rtree().query(boost::geometry::index::intersects(element_box),
                                                                std::back_inserter(candidates));
      double covered = 0;
      for (const auto& [box, cell] : candidates)
        {
          double a = 0, b = 0;
          if (!piece_in_cell(beam, e, mapping, cell, box, a, b))
            continue;
          if (agreed_cell(cache, position(beam, e, 0.5 * (a + b))) != cell)
            continue;
          pieces.emplace_back(a, b);
          covered += b - a;
          for (unsigned int q = 0; q < gauss.size(); ++q)
            {
              const double   xi = a + (b - a) * gauss.point(q)[0];
              const Point<3> p  = position(beam, e, xi);
              points.push_back({e, xi, gauss.weight(q) * 0.5 * (b - a) * l, cell,
                                mapping.transform_real_to_unit_cell(cell, p)});
            }
        }
      return covered;
    }

    /// Gauss-point-to-segment points of element e in this rank's cells; returns how many.
    int gpts_points(const BeamMesh& beam, std::size_t e, const GridTools::Cache<3>& cache, const QGauss<1>& gauss,
                    std::vector<IntegrationPoint>& points)
    {
      int found = 0;
      for (unsigned int q = 0; q < gauss.size(); ++q)
        {
          const double   xi   = 2 * gauss.point(q)[0] - 1;
          const Point<3> p    = position(beam, e, xi);
          const auto     cell = agreed_cell(cache, p);
          if (cell.state() != IteratorState::valid || !cell->is_locally_owned())
            continue;
          points.push_back({e, xi, gauss.weight(q) * beam.element_length(e), cell,
                            cache.get_mapping().transform_real_to_unit_cell(cell, p)});
          ++found;
        }
      return found;
    }

    /// The first point of element e no rank integrated (the element leaves the solid there):
    /// the start of the first gap between the pieces of all ranks (mortar), or the first Gauss
    /// point none found (gpts). Collective.
    Point<3> first_uncovered_point(const BeamMesh& beam, std::size_t e, CouplingMethod method,
                                   std::vector<std::pair<double, double>> pieces, const GridTools::Cache<3>& cache,
                                   const QGauss<1>& gauss, MPI_Comm comm)
    {
      if (method == CouplingMethod::gpts)
        {
          pieces.clear();
          for (unsigned int q = 0; q < gauss.size(); ++q)
            {
              const double xi   = 2 * gauss.point(q)[0] - 1;
              const auto   cell = agreed_cell(cache, position(beam, e, xi));
              if (cell.state() == IteratorState::valid && cell->is_locally_owned())
                pieces.emplace_back(xi, xi);
            }
        }
      std::vector<std::pair<double, double>> all;
      for (const auto& rank_pieces : Utilities::MPI::all_gather(comm, pieces))
        all.insert(all.end(), rank_pieces.begin(), rank_pieces.end());
      std::sort(all.begin(), all.end());
      if (method == CouplingMethod::gpts)
        {
          for (unsigned int q = 0; q < gauss.size(); ++q)
            {
              const double xi = 2 * gauss.point(q)[0] - 1;
              if (std::none_of(all.begin(), all.end(), [&](const auto& p) { return p.first == xi; }))
                return position(beam, e, xi);
            }
          return position(beam, e, -1.0);
        }
      double reached = -1.0;
      for (const auto& [a, b] : all)
        {
          if (a > reached + 1e-8)
            break;
          reached = std::max(reached, b);
        }
      return position(beam, e, reached);
    }
  } // namespace

  BeamSolidCoupling::BeamSolidCoupling(const BeamMesh& beam, const DoFHandler<3>& solid, CouplingMethod method,
                                       int gauss_points, const std::string& source,
                                       const std::function<unsigned int(std::size_t)>& node_owner, MPI_Comm comm)
      : comm_(comm)
      , n_beam_dofs_(beam.n_dofs())
  {
    const auto&               tria = solid.get_triangulation();
    const GridTools::Cache<3> cache(tria, StaticMappingQ1<3>::mapping);
    const QGauss<1>           gauss(gauss_points); // on [0, 1]

    // Every rank integrates the parts of all beam elements that lie in its own cells (the
    // beam mesh itself is known on every rank); coverage is checked over all ranks: an element
    // must be integrated along its whole length (mortar) or at all its Gauss points (gpts).
    std::vector<IntegrationPoint> points;
    std::vector<double>           coverage(beam.elements.size(), 0.0);
    std::vector<std::vector<std::pair<double, double>>> pieces(beam.elements.size());
    for (std::size_t e = 0; e < beam.elements.size(); ++e)
      coverage[e] = method == CouplingMethod::mortar ? mortar_points(beam, e, cache, gauss, points, pieces[e])
                                                     : gpts_points(beam, e, cache, gauss, points);
    Utilities::MPI::sum(coverage, comm, coverage);
    const double expected = method == CouplingMethod::mortar ? 2.0 : static_cast<double>(gauss.size());
    for (std::size_t e = 0; e < beam.elements.size(); ++e)
      if (std::abs(coverage[e] - expected) > 1e-8)
        {
          std::ostringstream where;
          where << first_uncovered_point(beam, e, method, pieces[e], cache, gauss, comm);
          throw std::invalid_argument(source + ": beam element " + std::to_string(e) + " has a point (" + where.str() +
                                      ") outside the solid");
        }
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
