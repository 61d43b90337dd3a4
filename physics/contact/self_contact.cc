#include "contact/self_contact.h"

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/mpi.h>
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

  std::vector<BodySegment> exchange_nearby_segments(const std::vector<BodySegment>& own, MPI_Comm comm)
  {
    // Box of the own segments (lo, hi; empty: lo > hi), gathered from every rank (O(ranks)).
    std::array<double, 4> box{{1e300, 1e300, -1e300, -1e300}};
    for (const auto& s : own)
      for (const auto& x : s.x)
        for (int d = 0; d < 2; ++d)
          {
            box[d]     = std::min(box[d], x[d]);
            box[2 + d] = std::max(box[2 + d], x[d]);
          }
    const auto boxes = dealii::Utilities::MPI::all_gather(comm, box);
    const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(comm);
    // Segments travel flattened: body, the two node ids, the four coordinates.
    std::vector<double> flat;
    for (const auto& s : own)
      flat.insert(flat.end(), {static_cast<double>(s.body), static_cast<double>(s.node[0]),
                               static_cast<double>(s.node[1]), s.x[0][0], s.x[0][1], s.x[1][0], s.x[1][1]});
    std::map<unsigned int, std::vector<double>> send;
    for (unsigned int r = 0; r < boxes.size(); ++r)
      if (r != rank && !own.empty() && boxes[r][0] <= box[2] && box[0] <= boxes[r][2] && boxes[r][1] <= box[3] &&
          box[1] <= boxes[r][3])
        send[r] = flat;
    std::vector<BodySegment> received;
    for (const auto& [from, data] : dealii::Utilities::MPI::some_to_some(comm, send))
      for (std::size_t i = 0; i + 7 <= data.size(); i += 7)
        {
          BodySegment s;
          s.body    = static_cast<unsigned int>(data[i]);
          s.node[0] = static_cast<dealii::types::global_dof_index>(data[i + 1]);
          s.node[1] = static_cast<dealii::types::global_dof_index>(data[i + 2]);
          s.x       = {{{{data[i + 3], data[i + 4]}}, {{data[i + 5], data[i + 6]}}}};
          received.push_back(s);
        }
    return received;
  }
} // namespace physics::contact
