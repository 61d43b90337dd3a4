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

    /// A beam element as the coupling sees it: global number, global nodes, reference positions
    /// of its ends (straight). Sent to every rank whose cells it may cross.
    struct CouplingElement
    {
      BeamIndex                id = 0;
      std::array<BeamIndex, 2> nodes{};
      std::array<Point<3>, 2>  x;
      double                   length() const { return x[1].distance(x[0]); }
    };

    struct IntegrationPoint
    {
      std::size_t  element; ///< in the list of elements this rank integrates
      double       xi, ds; ///< element coordinate, weight in reference arc length
      CellIterator cell;
      Point<3>     unit; ///< in the solid cell's reference coordinates
    };

    Point<3> position(const CouplingElement& element, double xi)
    {
      const Point<3>& a = element.x[0];
      const Point<3>& b = element.x[1];
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
    std::array<bool, 3> on_faces(const CouplingElement& element, const Mapping<3>& mapping,
                                 const CellIterator& cell, double xi)
    {
      const Point<3>      u = mapping.transform_real_to_unit_cell(cell, position(element, xi));
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
    double crossing(const CouplingElement& element, const Mapping<3>& mapping, const CellIterator& cell,
                    const std::array<bool, 3>& on, double in, double out)
    {
      for (int k = 0; k < 60 && std::abs(out - in) > 1e-15; ++k)
        {
          const double mid = 0.5 * (in + out);
          (inside(mapping, cell, position(element, mid), on) ? in : out) = mid;
        }
      return 0.5 * (in + out);
    }

    /// The part [a, b] of element e's centreline inside `cell` (hexahedra are convex, so it is one
    /// interval); false if the centreline misses the cell. A point inside is searched among
    /// samples of the part within the cell's bounding box, then both ends are found by bisection.
    bool piece_in_cell(const CouplingElement& element, const Mapping<3>& mapping, const CellIterator& cell,
                       const BoundingBox<3>& box, double& a, double& b)
    {
      // Slab clipping of the straight segment against the bounding box.
      const Point<3> p0 = position(element, -1.0), p1 = position(element, 1.0);
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
          if (!inside(mapping, cell, position(element, m)))
            continue;
          const auto on = on_faces(element, mapping, cell, m);
          a = inside(mapping, cell, position(element, -1.0), on) ? -1.0
                                                                         : crossing(element, mapping, cell, on, m, -1.0);
          b = inside(mapping, cell, position(element, 1.0), on) ? 1.0
                                                                        : crossing(element, mapping, cell, on, m, 1.0);
          return b > a;
        }
      return false;
    }

    /// Pieces shorter than this (in the element coordinate xi in [-1, 1]) are dropped. A cell is
    /// "inside" with 1e-10 of tolerance in its unit coordinates (so that neighbours agree on
    /// points on their common face), so an element that ends on a cell face, or crosses one, also
    /// yields a piece of ~2e-10 (up to ~2e-9 where the cell is longer than the element) in the
    /// cell across the face, overlapping the piece of the cell it lies in; agreed_cell() at its
    /// midpoint, on the face, may keep both. Measured on the block family (24 x 12 x 12 cells, 36
    /// fibres of 24 elements): 600 of 1464 pieces were such duplicates, 41 % of the coupling
    /// points, each coupling its element to the nodes of one more cell with entries of ~1e-10
    /// that still widen the coupling matrix's and the Schur complement's patterns. A genuine
    /// piece this short (an element grazing a cell's corner) adds at most 5e-9 of the element's
    /// length, below the coverage check's 1e-8.
    constexpr double min_piece = 5e-9;

    /// Segment-based ("mortar") integration points of `element` (number `index` in this rank's
    /// list) in this rank's cells: the pieces
    /// of the centreline inside each locally owned cell (candidates from the R-tree of their
    /// bounding boxes), each kept by the rank whose cell agreed_cell() names at its midpoint
    /// (a centreline along a face between cells is integrated once), with Gauss points on every
    /// piece. Returns the kept pieces' total length in xi.
    double mortar_points(const CouplingElement& element, std::size_t index, const GridTools::Cache<3>& cache,
                         const QGauss<1>& gauss, std::vector<IntegrationPoint>& points,
                         std::vector<std::pair<double, double>>& pieces)
    {
      const Mapping<3>& mapping = cache.get_mapping();
      const double      l       = element.length();
      const Point<3>    p0 = position(element, -1.0), p1 = position(element, 1.0);
      BoundingBox<3>    element_box(std::make_pair(p0, p0));
      element_box.merge_with(BoundingBox<3>(std::make_pair(p1, p1)));
      std::vector<std::pair<BoundingBox<3>, CellIterator>> candidates;
      cache.get_locally_owned_cell_bounding_boxes_rtree().query(boost::geometry::index::intersects(element_box),
                                                                std::back_inserter(candidates));
      double covered = 0;
      for (const auto& [box, cell] : candidates)
        {
          double a = 0, b = 0;
          if (!piece_in_cell(element, mapping, cell, box, a, b) || b - a < min_piece)
            continue;
          if (agreed_cell(cache, position(element, 0.5 * (a + b))) != cell)
            continue;
          pieces.emplace_back(a, b);
          covered += b - a;
          for (unsigned int q = 0; q < gauss.size(); ++q)
            {
              const double   xi = a + (b - a) * gauss.point(q)[0];
              const Point<3> p  = position(element, xi);
              points.push_back({index, xi, gauss.weight(q) * 0.5 * (b - a) * l, cell,
                                mapping.transform_real_to_unit_cell(cell, p)});
            }
        }
      return covered;
    }

    /// Gauss-point-to-segment points of `element` (number `index`) in this rank's cells, each
    /// also recorded as a piece (xi, xi); returns how many.
    int gpts_points(const CouplingElement& element, std::size_t index, const GridTools::Cache<3>& cache,
                    const QGauss<1>& gauss, std::vector<IntegrationPoint>& points,
                    std::vector<std::pair<double, double>>& pieces)
    {
      int found = 0;
      for (unsigned int q = 0; q < gauss.size(); ++q)
        {
          const double   xi   = 2 * gauss.point(q)[0] - 1;
          const Point<3> p    = position(element, xi);
          const auto     cell = agreed_cell(cache, p);
          if (cell.state() != IteratorState::valid || !cell->is_locally_owned())
            continue;
          points.push_back({index, xi, gauss.weight(q) * element.length(), cell,
                            cache.get_mapping().transform_real_to_unit_cell(cell, p)});
          pieces.emplace_back(xi, xi);
          ++found;
        }
      return found;
    }

    /// The first point of `element` no rank integrated (the element leaves the solid there),
    /// from the pieces of all ranks: the start of the first gap between them (mortar), or the
    /// first Gauss point none found (gpts).
    Point<3> first_uncovered_point(const CouplingElement& element, CouplingMethod method,
                                   std::vector<std::pair<double, double>> all, const QGauss<1>& gauss)
    {
      std::sort(all.begin(), all.end());
      if (method == CouplingMethod::gpts)
        {
          for (unsigned int q = 0; q < gauss.size(); ++q)
            {
              const double xi = 2 * gauss.point(q)[0] - 1;
              if (std::none_of(all.begin(), all.end(), [&](const auto& p) { return p.first == xi; }))
                return position(element, xi);
            }
          return position(element, -1.0);
        }
      double reached = -1.0;
      for (const auto& [a, b] : all)
        {
          if (a > reached + 1e-8)
            break;
          reached = std::max(reached, b);
        }
      return position(element, reached);
    }

    /// The bounding box of this rank's owned cells, widened by 1e-8 of its size (the inside test
    /// allows 1e-10 of a cell), as 6 numbers (lower, upper corner; none without owned cells).
    std::vector<double> owned_cells_box(const Triangulation<3>& tria)
    {
      std::vector<double> box;
      bool                first = true;
      BoundingBox<3>      all;
      for (const auto& cell : tria.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            if (first)
              all = cell->bounding_box();
            else
              all.merge_with(cell->bounding_box());
            first = false;
          }
      if (first)
        return box;
      all.extend(1e-8 * all.get_boundary_points().first.distance(all.get_boundary_points().second));
      for (const auto& corner : {all.get_boundary_points().first, all.get_boundary_points().second})
        for (unsigned int d = 0; d < 3; ++d)
          box.push_back(corner[d]);
      return box;
    }

    /// Every rank receives the elements that may cross its owned cells: each rank sends each of
    /// its elements to the ranks whose owned-cell box the element's box meets (one box per rank:
    /// a compact METIS part is covered well enough; a rank that receives an element outside its
    /// cells only finds no piece of it). Collective. Sorted by global number.
    std::vector<CouplingElement> elements_near_owned_cells(const DistributedBeam& beam, const Triangulation<3>& tria,
                                                           MPI_Comm comm)
    {
      const auto boxes = Utilities::MPI::all_gather(comm, owned_cells_box(tria));
      std::map<unsigned int, std::vector<double>> send; // per element: id, nodes, both ends
      for (std::size_t e = 0; e < beam.mesh.elements.size(); ++e)
        {
          const Point<3>& a = beam.mesh.nodes[beam.mesh.elements[e][0]];
          const Point<3>& b = beam.mesh.nodes[beam.mesh.elements[e][1]];
          for (unsigned int r = 0; r < boxes.size(); ++r)
            {
              bool meets = !boxes[r].empty();
              for (unsigned int d = 0; d < 3 && meets; ++d)
                meets = std::max(a[d], b[d]) >= boxes[r][d] && std::min(a[d], b[d]) <= boxes[r][3 + d];
              if (!meets)
                continue;
              auto& data = send[r];
              data.push_back(static_cast<double>(beam.element_ids[e]));
              for (int k = 0; k < 2; ++k)
                data.push_back(static_cast<double>(beam.global_node(e, k)));
              for (const Point<3>* x : {&a, &b})
                for (unsigned int d = 0; d < 3; ++d)
                  data.push_back((*x)[d]);
            }
        }
      std::vector<CouplingElement> elements;
      for (const auto& [rank, data] : Utilities::MPI::some_to_some(comm, send))
        for (std::size_t k = 0; k + 9 <= data.size(); k += 9)
          {
            CouplingElement element;
            element.id       = static_cast<BeamIndex>(data[k]);
            element.nodes    = {{static_cast<BeamIndex>(data[k + 1]), static_cast<BeamIndex>(data[k + 2])}};
            element.x[0]     = Point<3>(data[k + 3], data[k + 4], data[k + 5]);
            element.x[1]     = Point<3>(data[k + 6], data[k + 7], data[k + 8]);
            elements.push_back(element);
          }
      std::sort(elements.begin(), elements.end(), [](const auto& x, const auto& y) { return x.id < y.id; });
      return elements;
    }

    /// The coverage of every element this rank integrated (length in xi or number of Gauss
    /// points) and its pieces, summed and gathered at the element's owner (collective). Returns,
    /// of this rank's own elements (by local number), the smallest global number whose coverage
    /// differs from `expected`, with its point outside the solid; numbers::invalid_dof_index
    /// if none.
    std::pair<BeamIndex, Point<3>> first_uncovered_element(
        const DistributedBeam& beam, const std::vector<CouplingElement>& elements, const std::vector<double>& coverage,
        const std::vector<std::vector<std::pair<double, double>>>& pieces, CouplingMethod method, double expected,
        const QGauss<1>& gauss, MPI_Comm comm)
    {
      std::map<unsigned int, std::vector<double>> send; // per element: id, coverage, n pieces, pieces
      for (std::size_t i = 0; i < elements.size(); ++i)
        {
          auto& data = send[beam.owner(elements[i].nodes[0])];
          data.insert(data.end(),
                      {static_cast<double>(elements[i].id), coverage[i], static_cast<double>(pieces[i].size())});
          for (const auto& [a, b] : pieces[i])
            data.insert(data.end(), {a, b});
        }
      std::map<BeamIndex, std::pair<double, std::vector<std::pair<double, double>>>> mine;
      for (const auto& [rank, data] : Utilities::MPI::some_to_some(comm, send))
        for (std::size_t k = 0; k < data.size();)
          {
            auto&             element = mine[static_cast<BeamIndex>(data[k])];
            const std::size_t n       = static_cast<std::size_t>(data[k + 2]);
            element.first += data[k + 1];
            for (std::size_t i = 0; i < n; ++i)
              element.second.emplace_back(data[k + 3 + 2 * i], data[k + 4 + 2 * i]);
            k += 3 + 2 * n;
          }
      for (std::size_t e = 0; e < beam.mesh.elements.size(); ++e) // ascending global numbers
        {
          const auto it = mine.find(beam.element_ids[e]);
          if (it != mine.end() && std::abs(it->second.first - expected) <= 1e-8)
            continue;
          CouplingElement element;
          element.x = {{beam.mesh.nodes[beam.mesh.elements[e][0]], beam.mesh.nodes[beam.mesh.elements[e][1]]}};
          std::vector<std::pair<double, double>> all_pieces;
          if (it != mine.end())
            all_pieces = it->second.second;
          return {beam.element_ids[e], first_uncovered_point(element, method, all_pieces, gauss)};
        }
      return {numbers::invalid_dof_index, Point<3>()};
    }
  } // namespace

  BeamSolidCoupling::BeamSolidCoupling(const DistributedBeam& beam, const DoFHandler<3>& solid, CouplingMethod method,
                                       int gauss_points, const std::string& source, MPI_Comm comm)
      : comm_(comm)
      , n_beam_dofs_(beam.n_dofs())
  {
    const auto&               tria = solid.get_triangulation();
    const GridTools::Cache<3> cache(tria, StaticMappingQ1<3>::mapping);
    const QGauss<1>           gauss(gauss_points); // on [0, 1]

    // Every rank integrates the parts of the elements near its cells that lie in its own cells;
    // coverage is checked at each element's owner: an element must be integrated along its
    // whole length (mortar) or at all its Gauss points (gpts).
    const std::vector<CouplingElement> elements = elements_near_owned_cells(beam, tria, comm);
    std::vector<IntegrationPoint>      points;
    std::vector<double>                coverage(elements.size(), 0.0);
    std::vector<std::vector<std::pair<double, double>>> pieces(elements.size());
    for (std::size_t i = 0; i < elements.size(); ++i)
      coverage[i] = method == CouplingMethod::mortar
                        ? mortar_points(elements[i], i, cache, gauss, points, pieces[i])
                        : gpts_points(elements[i], i, cache, gauss, points, pieces[i]);
    const double expected = method == CouplingMethod::mortar ? 2.0 : static_cast<double>(gauss.size());
    const auto [uncovered, where] =
        first_uncovered_element(beam, elements, coverage, pieces, method, expected, gauss, comm);
    const BeamIndex first_uncovered = Utilities::MPI::min(uncovered, comm);
    std::string     error;
    if (first_uncovered != numbers::invalid_dof_index && uncovered == first_uncovered)
      {
        std::ostringstream point;
        point << where;
        error = source + ": beam element " + std::to_string(uncovered) + " has a point (" + point.str() +
                ") outside the solid";
      }
    throw_if_any_rank_failed(error, comm);
    n_points_            = Utilities::MPI::sum(points.size(), comm);
    max_points_per_rank_ = Utilities::MPI::max(points.size(), comm);

    // Partial rows j of B = [D, -M] from this rank's points, row j -> (x-component column ->
    // weight); the y and z columns follow the x column (beam: 6 DOFs per node, solid: node-major).
    RowPieces                     partial;
    std::map<GlobalIndex, double> partial_kappa;
    for (const auto& point : points)
      {
        const auto&  nodes = elements[point.element].nodes;
        const double l     = elements[point.element].length();
        const auto   h     = centreline_weights(point.xi, l);
        const typename DoFHandler<3>::active_cell_iterator cell(&tria, point.cell->level(), point.cell->index(), &solid);
        for (int a = 0; a < 2; ++a)
          {
            const BeamIndex j   = nodes[a];
            const double    phi = a == 0 ? 0.5 * (1 - point.xi) : 0.5 * (1 + point.xi);
            partial_kappa[j] += phi * point.ds;
            // D: beam position / tangent unknowns of both element nodes.
            for (int k = 0; k < 4; ++k)
              partial[j][6 * nodes[k / 2] + 3 * (k % 2)] += phi * h[k] * point.ds;
            // -M: solid vertex unknowns of the cell, trilinear shape functions.
            for (unsigned int v = 0; v < GeometryInfo<3>::vertices_per_cell; ++v)
              partial[j][n_beam_dofs_ + cell->vertex_dof_index(v, 0)] -=
                  phi * GeometryInfo<3>::d_linear_shape_function(point.unit, v) * point.ds;
          }
      }

    // Whole rows and kappa at the owners of their multiplier nodes.
    const auto node_owner = [&](GlobalIndex n) { return beam.owner(n); };
    for (const auto& [j, k] : send_entries_to_owners(partial_kappa, node_owner, comm))
      kappa_[j] = k;
    std::set<GlobalIndex> solid_dofs, beam_dofs;
    for (const auto& [j, row] : send_rows_to_owners(std::move(partial), node_owner, comm))
      {
        auto& entries = rows_[j];
        for (const auto& [column, weight] : row)
          {
            entries.push_back({{{column, column + 1, column + 2}}, weight});
            for (unsigned int c = 0; c < 3; ++c)
              if (column >= n_beam_dofs_)
                solid_dofs.insert(column - n_beam_dofs_ + c);
              else
                beam_dofs.insert(column + c);
          }
      }
    solid_dofs_.assign(solid_dofs.begin(), solid_dofs.end());
    beam_dofs_.assign(beam_dofs.begin(), beam_dofs.end());
  }

  std::map<BeamIndex, std::array<double, 3>> BeamSolidCoupling::gaps(const TrilinosWrappers::MPI::Vector& beam,
                                                                     const TrilinosWrappers::MPI::Vector& solid) const
  {
    std::map<BeamIndex, std::array<double, 3>> g;
    for (const auto& [j, row] : rows_)
      {
        auto& gap = g[j];
        gap       = {{0.0, 0.0, 0.0}};
        for (const auto& entry : row)
          for (unsigned int c = 0; c < 3; ++c)
            {
              const GlobalIndex col   = entry.columns[c];
              const double      value = col < n_beam_dofs_ ? beam[col] : solid[col - n_beam_dofs_];
              gap[c] += entry.weight * value;
            }
      }
    return g;
  }

  RowPieces BeamSolidCoupling::penalty_matrix(double epsilon,
                                              const std::function<unsigned int(GlobalIndex)>& row_owner) const
  {
    // Node j contributes eps / kappa_j (B_j)^T B_j: every pair of its entries, per component.
    RowPieces matrix;
    for (const auto& [j, row] : rows_)
      {
        const auto kappa = kappa_.find(j);
        if (kappa == kappa_.end() || kappa->second <= 0)
          continue;
        const double scale = epsilon / kappa->second;
        for (const auto& a : row)
          for (unsigned int c = 0; c < 3; ++c)
            {
              auto& matrix_row = matrix[a.columns[c]];
              for (const auto& b : row)
                matrix_row[b.columns[c]] += scale * a.weight * b.weight;
            }
      }
    return send_rows_to_owners(std::move(matrix), row_owner, comm_);
  }
} // namespace physics::beam_solid
