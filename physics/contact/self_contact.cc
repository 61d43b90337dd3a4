#include "contact/self_contact.h"

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/mpi.h>
#include <deal.II/boost_adaptors/bounding_box.h>
#include <deal.II/numerics/rtree.h>

#include <algorithm>
#include <sstream>

namespace physics::contact
{
  namespace
  {
    using P2 = std::array<double, 2>;
    using P3 = std::array<double, 3>;

    /// Do the segments (a, b) and (c, d) cross (a proper intersection: each separates the other's
    /// end points)?
    bool segments_cross(const P2& a, const P2& b, const P2& c, const P2& d)
    {
      auto side = [](const P2& p, const P2& q, const P2& r) {
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
      };
      return side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0;
    }

    /// Six times the signed volume of the tetrahedron (a, b, c, d): det[b - a, c - a, d - a].
    double orient(const P3& a, const P3& b, const P3& c, const P3& d)
    {
      const P3 u{{b[0] - a[0], b[1] - a[1], b[2] - a[2]}}, v{{c[0] - a[0], c[1] - a[1], c[2] - a[2]}},
          w{{d[0] - a[0], d[1] - a[1], d[2] - a[2]}};
      return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
             u[2] * (v[0] * w[1] - v[1] * w[0]);
    }

    /// Does the segment (p, q) pass through the triangle (a, b, c)? Its end points lie strictly on
    /// either side of the triangle's plane, and the line through them meets the closed triangle
    /// (the three edge orientations do not disagree in sign; a zero is a line through an edge,
    /// e.g. the diagonal along which a quadrilateral was split).
    bool segment_through_triangle(const P3& p, const P3& q, const P3& a, const P3& b, const P3& c)
    {
      if (!(orient(a, b, c, p) * orient(a, b, c, q) < 0))
        return false;
      const double s0 = orient(p, q, a, b), s1 = orient(p, q, b, c), s2 = orient(p, q, c, a);
      return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
    }

    /// Does an edge of face `a` pass through face `b` (split into a fan of triangles)?
    bool edge_through_face(const BodyFacet<3>& a, const BodyFacet<3>& b)
    {
      const std::size_t n = a.x.size();
      for (std::size_t e = 0; e < n; ++e)
        for (std::size_t t = 1; t + 1 < b.x.size(); ++t)
          if (segment_through_triangle(a.x[e], a.x[(e + 1) % n], b.x[0], b.x[t], b.x[t + 1]))
            return true;
      return false;
    }

    bool facets_cross(const BodyFacet<2>& a, const BodyFacet<2>& b)
    {
      return segments_cross(a.x[0], a.x[1], b.x[0], b.x[1]);
    }

    bool facets_cross(const BodyFacet<3>& a, const BodyFacet<3>& b)
    {
      return edge_through_face(a, b) || edge_through_face(b, a);
    }

    template <int dim>
    bool share_a_node(const BodyFacet<dim>& a, const BodyFacet<dim>& b)
    {
      return std::any_of(a.node.begin(), a.node.end(),
                         [&](auto n) { return std::find(b.node.begin(), b.node.end(), n) != b.node.end(); });
    }

    template <int dim>
    dealii::BoundingBox<dim> box_of(const BodyFacet<dim>& facet)
    {
      dealii::Point<dim> lo, hi;
      for (int d = 0; d < dim; ++d)
        {
          lo[d] = hi[d] = facet.x[0][d];
          for (const auto& x : facet.x)
            {
              lo[d] = std::min(lo[d], x[d]);
              hi[d] = std::max(hi[d], x[d]);
            }
        }
      return dealii::BoundingBox<dim>(std::make_pair(lo, hi));
    }
  } // namespace

  template <int dim>
  std::string find_self_crossing(const std::vector<BodyFacet<dim>>& facets)
  {
    using Box = dealii::BoundingBox<dim>;
    std::vector<std::pair<Box, unsigned int>> boxes;
    for (unsigned int i = 0; i < facets.size(); ++i)
      boxes.emplace_back(box_of(facets[i]), i);
    const auto tree = dealii::pack_rtree(boxes);
    for (unsigned int i = 0; i < facets.size(); ++i)
      {
        std::vector<std::pair<Box, unsigned int>> hits;
        tree.query(boost::geometry::index::intersects(boxes[i].first), std::back_inserter(hits));
        const auto& a = facets[i];
        for (const auto& hit : hits)
          {
            const auto& b = facets[hit.second];
            if (hit.second <= i || a.body != b.body || share_a_node(a, b) || !facets_cross(a, b))
              continue;
            std::ostringstream text;
            text << "body " << a.body << " penetrates itself near (";
            for (int d = 0; d < dim; ++d)
              {
                double centre = 0;
                for (const auto& x : a.x)
                  centre += x[d] / a.x.size();
                text << (d > 0 ? ", " : "") << centre;
              }
            text << ")";
            return text.str();
          }
      }
    return "";
  }

  template <int dim>
  std::vector<BodyFacet<dim>> exchange_nearby_facets(const std::vector<BodyFacet<dim>>& own, MPI_Comm comm)
  {
    // Box of the own faces (lo, hi; empty: lo > hi), gathered from every rank (O(ranks)).
    std::array<double, 2 * dim> box;
    std::fill(box.begin(), box.begin() + dim, 1e300);
    std::fill(box.begin() + dim, box.end(), -1e300);
    for (const auto& s : own)
      for (const auto& x : s.x)
        for (int d = 0; d < dim; ++d)
          {
            box[d]       = std::min(box[d], x[d]);
            box[dim + d] = std::max(box[dim + d], x[d]);
          }
    const auto         boxes = dealii::Utilities::MPI::all_gather(comm, box);
    const unsigned int rank  = dealii::Utilities::MPI::this_mpi_process(comm);
    auto               meets = [&](const std::array<double, 2 * dim>& other) {
      for (int d = 0; d < dim; ++d)
        if (other[d] > box[dim + d] || box[d] > other[dim + d])
          return false;
      return true;
    };
    // Faces travel flattened: body, vertex count n, the n node ids, the n * dim coordinates.
    std::vector<double> flat;
    for (const auto& s : own)
      {
        flat.push_back(static_cast<double>(s.body));
        flat.push_back(static_cast<double>(s.node.size()));
        for (const auto n : s.node)
          flat.push_back(static_cast<double>(n));
        for (const auto& x : s.x)
          flat.insert(flat.end(), x.begin(), x.end());
      }
    std::map<unsigned int, std::vector<double>> send;
    for (unsigned int r = 0; r < boxes.size(); ++r)
      if (r != rank && !own.empty() && meets(boxes[r]))
        send[r] = flat;
    std::vector<BodyFacet<dim>> received;
    for (const auto& [from, data] : dealii::Utilities::MPI::some_to_some(comm, send))
      for (std::size_t i = 0; i + 2 <= data.size();)
        {
          BodyFacet<dim> s;
          s.body              = static_cast<unsigned int>(data[i]);
          const std::size_t n = static_cast<std::size_t>(data[i + 1]);
          i += 2;
          for (std::size_t k = 0; k < n; ++k)
            s.node.push_back(static_cast<dealii::types::global_dof_index>(data[i++]));
          s.x.resize(n);
          for (auto& x : s.x)
            for (int d = 0; d < dim; ++d)
              x[d] = data[i++];
          received.push_back(s);
        }
    return received;
  }

  template std::string               find_self_crossing(const std::vector<BodyFacet<2>>&);
  template std::string               find_self_crossing(const std::vector<BodyFacet<3>>&);
  template std::vector<BodyFacet<2>> exchange_nearby_facets(const std::vector<BodyFacet<2>>&, MPI_Comm);
  template std::vector<BodyFacet<3>> exchange_nearby_facets(const std::vector<BodyFacet<3>>&, MPI_Comm);
} // namespace physics::contact
