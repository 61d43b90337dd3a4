#include "contact/self_contact.h"

#include <deal.II/base/bounding_box.h>
#include <deal.II/boost_adaptors/bounding_box.h>
#include <deal.II/numerics/rtree.h>

#include <sstream>

namespace physics::contact
{
  namespace
  {
    /// Do the segments (a, b) and (c, d) cross (a proper intersection: each separates the other's
    /// end points)?
    bool segments_cross(const std::array<double, 2>& a, const std::array<double, 2>& b,
                        const std::array<double, 2>& c, const std::array<double, 2>& d)
    {
      auto side = [](const std::array<double, 2>& p, const std::array<double, 2>& q, const std::array<double, 2>& r) {
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
      };
      return side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0;
    }
  } // namespace

  std::string find_self_crossing(const std::vector<BodySegment>& segments)
  {
    using Box = dealii::BoundingBox<2>;
    std::vector<std::pair<Box, unsigned int>> boxes;
    for (unsigned int i = 0; i < segments.size(); ++i)
      {
        dealii::Point<2> lo, hi;
        for (int d = 0; d < 2; ++d)
          {
            lo[d] = std::min(segments[i].x[0][d], segments[i].x[1][d]);
            hi[d] = std::max(segments[i].x[0][d], segments[i].x[1][d]);
          }
        boxes.emplace_back(Box(std::make_pair(lo, hi)), i);
      }
    const auto tree = dealii::pack_rtree(boxes);
    for (unsigned int i = 0; i < segments.size(); ++i)
      {
        std::vector<std::pair<Box, unsigned int>> hits;
        tree.query(boost::geometry::index::intersects(boxes[i].first), std::back_inserter(hits));
        const auto& a = segments[i];
        for (const auto& hit : hits)
          {
            const auto& b = segments[hit.second];
            if (hit.second <= i || a.body != b.body)
              continue;
            const bool shared = a.node[0] == b.node[0] || a.node[0] == b.node[1] || a.node[1] == b.node[0] ||
                                a.node[1] == b.node[1];
            if (!shared && segments_cross(a.x[0], a.x[1], b.x[0], b.x[1]))
              {
                std::ostringstream text;
                text << "body " << a.body << " penetrates itself near (" << 0.5 * (a.x[0][0] + a.x[1][0]) << ", "
                     << 0.5 * (a.x[0][1] + a.x[1][1]) << ")";
                return text.str();
              }
          }
      }
    return "";
  }
} // namespace physics::contact
