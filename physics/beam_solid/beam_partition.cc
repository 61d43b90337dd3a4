#include "beam_solid/beam_partition.h"

#include <deal.II/base/mpi.h>

#include <boost/serialization/vector.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace physics::beam_solid
{
  using namespace dealii;

  std::size_t DistributedBeam::local_node(BeamIndex n) const
  {
    const auto it = std::lower_bound(node_ids.begin(), node_ids.end(), n);
    if (it == node_ids.end() || *it != n)
      throw std::logic_error("beam node " + std::to_string(n) + " is not stored on this rank");
    return static_cast<std::size_t>(it - node_ids.begin());
  }

  IndexSet DistributedBeam::owned_dofs() const
  {
    IndexSet dofs(n_dofs());
    dofs.add_range(6 * first_owned, 6 * end_owned);
    return dofs;
  }

  IndexSet DistributedBeam::stored_dofs() const
  {
    IndexSet dofs(n_dofs());
    for (const BeamIndex n : node_ids)
      dofs.add_range(6 * n, 6 * n + 6);
    dofs.compress();
    return dofs;
  }

  DistributedBeam empty_part(BeamIndex n_nodes, BeamIndex n_elements, unsigned int rank, unsigned int n_ranks)
  {
    DistributedBeam part;
    part.n_nodes     = n_nodes;
    part.n_elements  = n_elements;
    part.n_ranks     = n_ranks;
    part.first_owned = n_nodes * rank / n_ranks;
    part.end_owned   = n_nodes * (rank + 1) / n_ranks;
    return part;
  }

  void add_share(const BeamMesh& piece, BeamIndex node_offset, BeamIndex element_offset, DistributedBeam& part)
  {
    std::vector<bool> stored(piece.nodes.size(), false);
    for (std::size_t i = 0; i < piece.nodes.size(); ++i)
      stored[i] = part.owns(node_offset + i);
    std::vector<std::size_t> owned_elements;
    for (std::size_t e = 0; e < piece.elements.size(); ++e)
      if (part.owns(node_offset + piece.elements[e][0]))
        {
          owned_elements.push_back(e);
          for (const int n : piece.elements[e])
            stored[n] = true;
        }
    std::vector<int> local(piece.nodes.size(), -1);
    for (std::size_t i = 0; i < piece.nodes.size(); ++i)
      if (stored[i])
        {
          local[i] = static_cast<int>(part.node_ids.size());
          part.node_ids.push_back(node_offset + i);
          part.mesh.nodes.push_back(piece.nodes[i]);
          part.mesh.tangents.push_back(piece.tangents[i]);
        }
    for (const std::size_t e : owned_elements)
      {
        part.element_ids.push_back(element_offset + e);
        part.mesh.elements.push_back({{local[piece.elements[e][0]], local[piece.elements[e][1]]}});
      }
  }

  namespace
  {
    /// A part packed as doubles (global numbers are exact below 2^53): n_nodes, n_elements
    /// (global), the stored nodes (id, position, tangent), the elements (id, local ends).
    std::vector<double> pack(const DistributedBeam& part)
    {
      std::vector<double> data{static_cast<double>(part.n_nodes), static_cast<double>(part.n_elements),
                               static_cast<double>(part.node_ids.size())};
      for (std::size_t n = 0; n < part.node_ids.size(); ++n)
        {
          data.push_back(static_cast<double>(part.node_ids[n]));
          for (int c = 0; c < 3; ++c)
            data.push_back(part.mesh.nodes[n][c]);
          for (int c = 0; c < 3; ++c)
            data.push_back(part.mesh.tangents[n][c]);
        }
      data.push_back(static_cast<double>(part.element_ids.size()));
      for (std::size_t e = 0; e < part.element_ids.size(); ++e)
        data.insert(data.end(), {static_cast<double>(part.element_ids[e]),
                                 static_cast<double>(part.mesh.elements[e][0]),
                                 static_cast<double>(part.mesh.elements[e][1])});
      return data;
    }

    /// The stored nodes and elements of a packed part into `part` (counts and block set).
    void unpack(const std::vector<double>& data, DistributedBeam& part)
    {
      std::size_t k    = 2;
      auto        next = [&]() { return data.at(k++); };
      const auto  n_nodes = static_cast<std::size_t>(next());
      for (std::size_t i = 0; i < n_nodes; ++i)
        {
          part.node_ids.push_back(static_cast<BeamIndex>(next()));
          Point<3>     x;
          Tensor<1, 3> t;
          for (int c = 0; c < 3; ++c)
            x[c] = next();
          for (int c = 0; c < 3; ++c)
            t[c] = next();
          part.mesh.nodes.push_back(x);
          part.mesh.tangents.push_back(t);
        }
      const auto n_elements = static_cast<std::size_t>(next());
      for (std::size_t i = 0; i < n_elements; ++i)
        {
          part.element_ids.push_back(static_cast<BeamIndex>(next()));
          const int a = static_cast<int>(next()), b = static_cast<int>(next());
          part.mesh.elements.push_back({{a, b}});
        }
    }
  } // namespace

  DistributedBeam distribute_beam(const BeamMesh& whole, MPI_Comm comm)
  {
    const unsigned int rank = Utilities::MPI::this_mpi_process(comm), n_ranks = Utilities::MPI::n_mpi_processes(comm);
    std::map<unsigned int, std::vector<double>> parts;
    if (rank == 0)
      for (unsigned int r = 0; r < n_ranks; ++r)
        {
          DistributedBeam part = empty_part(whole.nodes.size(), whole.elements.size(), r, n_ranks);
          add_share(whole, 0, 0, part);
          parts[r] = pack(part);
        }
    const auto  received = Utilities::MPI::some_to_some(comm, parts);
    const auto& data     = received.at(0);
    DistributedBeam part =
        empty_part(static_cast<BeamIndex>(data.at(0)), static_cast<BeamIndex>(data.at(1)), rank, n_ranks);
    unpack(data, part);
    return part;
  }

  CrossedCells::CrossedCells(const std::vector<double>& size, const std::vector<int>& cells)
  {
    std::size_t n = 1;
    for (int d = 0; d < 3; ++d)
      {
        size_[d]  = size.at(d);
        cells_[d] = cells.at(d);
        n *= static_cast<std::size_t>(cells_[d]);
      }
    flags_.assign(n, 0);
  }

  void CrossedCells::mark(const BeamMesh& mesh)
  {
    std::array<double, 3> width;
    for (int d = 0; d < 3; ++d)
      width[d] = size_[d] / cells_[d];
    const double spacing = 0.25 * *std::min_element(width.begin(), width.end());
    const double tol     = 1e-10 * spacing; // a sample this close to a face lies on it
    for (const auto& element : mesh.elements)
      {
        const Point<3>& a       = mesh.nodes[element[0]];
        const Point<3>& b       = mesh.nodes[element[1]];
        const int       samples = 1 + static_cast<int>(std::ceil(a.distance(b) / spacing));
        for (int s = 0; s <= samples; ++s)
          {
            const Point<3>     x = a + (b - a) * (static_cast<double>(s) / samples);
            std::array<int, 3> lo, hi;
            bool               inside = true;
            for (int d = 0; d < 3; ++d)
              {
                lo[d]  = std::max(0, static_cast<int>(std::floor((x[d] - tol) / width[d])));
                hi[d]  = std::min(cells_[d] - 1, static_cast<int>(std::floor((x[d] + tol) / width[d])));
                inside = inside && lo[d] <= hi[d];
              }
            if (!inside)
              continue;
            for (int k = lo[2]; k <= hi[2]; ++k)
              for (int j = lo[1]; j <= hi[1]; ++j)
                for (int i = lo[0]; i <= hi[0]; ++i)
                  flags_[index(i, j, k)] = 1;
          }
      }
  }

  bool CrossedCells::contains(const Point<3>& centre) const
  {
    std::array<int, 3> ijk;
    for (int d = 0; d < 3; ++d)
      ijk[d] = std::clamp(static_cast<int>(std::floor(centre[d] / size_[d] * cells_[d])), 0, cells_[d] - 1);
    return flags_[index(ijk[0], ijk[1], ijk[2])] != 0;
  }

  std::size_t CrossedCells::n_marked() const
  {
    return static_cast<std::size_t>(std::count(flags_.begin(), flags_.end(), 1));
  }
} // namespace physics::beam_solid
