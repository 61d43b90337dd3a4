// Non-matching FSI interfaces: the faces of each side gathered from every rank and the dual
// mortar weights P = D^-1 M of the fluid's interface nodes (interface_nodes.h). The integration
// of one slave face against one master face is the contact class's (common/mortar_integration.h:
// auxiliary plane of the slave face, projection, clipping, Gauss rules on the overlap, dual
// multiplier basis).
//
// Why P = D^-1 M. The kinematic condition holds weakly on the slave (fluid) side:
//   int_Gamma Phi_j (u^F - u^S) ds = 0 for every multiplier basis function Phi_j,
// i.e. D u^F_Gamma = M u^S_Gamma with D_jk = int Phi_j N_k^F, M_jl = int Phi_j N_l^S. With the
// dual basis (int Phi_j N_k^F = delta_jk D_jj on every slave face) D is diagonal, so the fluid's
// interface values are u^F_j = sum_l (M_jl / D_jj) u^S_l without a solve; the same P moves the
// ALE interface, and by duality the fluid's interface rows reach the structure as P^T R^F_Gamma
// (condensed_fsi.h). Since sum_l N_l^S = 1, a slave node whose faces the master surface covers
// has sum_l P_jl = int Phi_j / D_jj = 1 (constants pass unchanged); a row sum off 1 means the
// two surfaces do not overlap there.
#include "common/mortar_integration.h"
#include "fsi/interface_nodes.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace physics::fsi
{
  using namespace dealii;

  template <int dim>
  InterfaceFaces<dim> gather_interface_faces(const DoFHandler<dim>& dofs, unsigned int components,
                                             const std::function<bool(types::boundary_id)>& on_interface,
                                             MPI_Comm                                       comm)
  {
    // This rank's faces (each boundary face belongs to one cell: its owner sends it), flat:
    // per face its vertices in cyclic order (3D: deal.II's lexicographic 0, 1, 2, 3 -> 0, 1, 3,
    // 2), coordinates and DOFs, reversed where the right-hand rule points into the cell.
    constexpr unsigned int   n         = dim == 2 ? 2 : 4;
    const unsigned int       cyclic[4] = {0, 1, 3, 2};
    std::vector<double>      x;
    std::vector<GlobalIndex> indices;
    for (const auto& cell : dofs.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int f : cell->face_indices())
          if (cell->at_boundary(f) && on_interface(cell->face(f)->boundary_id()))
            {
              const auto                  face = cell->face(f);
              std::array<unsigned int, 4> order{};
              std::array<Point<dim>, 4>   p;
              for (unsigned int k = 0; k < n; ++k)
                {
                  order[k] = dim == 2 ? k : cyclic[k];
                  p[k]     = face->vertex(order[k]);
                }
              Tensor<1, dim> normal;
              if constexpr (dim == 2)
                {
                  normal[0] = p[1][1] - p[0][1];
                  normal[1] = p[0][0] - p[1][0];
                }
              else
                normal = cross_product_3d(p[2] - p[0], p[3] - p[1]);
              if (normal * (face->center() - cell->center()) < 0)
                std::reverse(order.begin(), order.begin() + n);
              for (unsigned int k = 0; k < n; ++k)
                {
                  for (unsigned int d = 0; d < dim; ++d)
                    x.push_back(face->vertex(order[k])[d]);
                  for (unsigned int c = 0; c < components; ++c)
                    indices.push_back(face->vertex_dof_index(order[k], c));
                }
            }
    const auto all_x = Utilities::MPI::all_gather(comm, x);
    const auto all_i = Utilities::MPI::all_gather(comm, indices);

    // Every node once (by its first DOF), faces as node numbers.
    InterfaceFaces<dim> result;
    result.nodes.components = components;
    std::map<GlobalIndex, unsigned int> node_of;
    for (std::size_t r = 0; r < all_x.size(); ++r)
      for (std::size_t v = 0; v * dim < all_x[r].size(); v += n)
        {
          std::vector<unsigned int> face;
          for (unsigned int k = 0; k < n; ++k)
            {
              const std::size_t vertex = v + k;
              const GlobalIndex first  = all_i[r][vertex * components];
              const auto [it, added] =
                  node_of.emplace(first, static_cast<unsigned int>(result.nodes.positions.size()));
              if (added)
                {
                  Point<dim> position;
                  for (unsigned int d = 0; d < dim; ++d)
                    position[d] = all_x[r][vertex * dim + d];
                  result.nodes.positions.push_back(position);
                  for (unsigned int c = 0; c < components; ++c)
                    result.nodes.dofs.push_back(all_i[r][vertex * components + c]);
                }
              face.push_back(it->second);
            }
          result.faces.push_back(std::move(face));
        }
    return result;
  }

  namespace
  {
    template <int dim>
    std::vector<mortar::Point<double, dim>> face_points(const InterfaceFaces<dim>& F, std::size_t f)
    {
      std::vector<mortar::Point<double, dim>> x;
      for (const unsigned int node : F.faces[f])
        {
          mortar::Point<double, dim> p;
          for (unsigned int d = 0; d < dim; ++d)
            p[d] = F.nodes.positions[node][d];
          x.push_back(p);
        }
      return x;
    }

    /// A face's bounding box, grown by its diameter (faces of the other side that face it may
    /// lie a little off a curved surface's facets).
    template <int dim>
    std::pair<Point<dim>, Point<dim>> grown_box(const InterfaceFaces<dim>& F, std::size_t f)
    {
      Point<dim> low = F.nodes.positions[F.faces[f][0]], high = low;
      for (const unsigned int node : F.faces[f])
        for (unsigned int d = 0; d < dim; ++d)
          {
            low[d]  = std::min(low[d], F.nodes.positions[node][d]);
            high[d] = std::max(high[d], F.nodes.positions[node][d]);
          }
      const double size = low.distance(high);
      for (unsigned int d = 0; d < dim; ++d)
        {
          low[d] -= size;
          high[d] += size;
        }
      return {low, high};
    }
  } // namespace

  template <int dim>
  InterfacePartners dual_mortar_partners(const InterfaceFaces<dim>& from, const InterfaceFaces<dim>& to,
                                         unsigned int components, const std::string& what)
  {
    // D (its diagonal) and M per slave node, summed over all overlapping face pairs.
    std::vector<double>                            D(from.nodes.positions.size(), 0.0);
    std::vector<std::map<unsigned int, double>>    M(from.nodes.positions.size());
    std::vector<std::pair<Point<dim>, Point<dim>>> master_boxes;
    for (std::size_t m = 0; m < to.faces.size(); ++m)
      master_boxes.push_back(grown_box(to, m));
    for (std::size_t s = 0; s < from.faces.size(); ++s)
      {
        const auto xs  = face_points(from, s);
        const auto box = grown_box(from, s);
        for (std::size_t m = 0; m < to.faces.size(); ++m)
          {
            bool apart = false;
            for (unsigned int d = 0; d < dim; ++d)
              apart = apart || box.second[d] < master_boxes[m].first[d] ||
                      master_boxes[m].second[d] < box.first[d];
            if (apart)
              continue;
            const auto pair = mortar::integrate_pair<double, dim>(xs, face_points(to, m), true);
            if (!pair.overlap)
              continue;
            for (std::size_t i = 0; i < xs.size(); ++i)
              {
                const unsigned int j = from.faces[s][i];
                D[j] += pair.D[i][i];
                for (std::size_t k = 0; k < to.faces[m].size(); ++k)
                  M[j][to.faces[m][k]] += pair.M[i][k];
              }
          }
      }

    // P = D^-1 M, checked row by row, expanded to the DOFs of each component.
    InterfacePartners partners;
    for (std::size_t j = 0; j < D.size(); ++j)
      {
        double sum = 0;
        for (const auto& [l, m] : M[j])
          sum += m;
        const double row_sum = D[j] > 0 ? sum / D[j] : 0.0;
        if (!(std::abs(row_sum - 1) <= 1e-3))
          {
            std::string where;
            for (unsigned int d = 0; d < dim; ++d)
              where += (d > 0 ? ", " : "") + Utilities::to_string(from.nodes.positions[j][d]);
            throw std::invalid_argument(what + ": the fluid interface node at (" + where +
                                        ") does not face the structure's interface (dual mortar row sum " +
                                        Utilities::to_string(row_sum) +
                                        ", expected 1): the two interface surfaces must overlap");
          }
        // Weights at round-off level (exact zeros on matching faces) are dropped.
        for (unsigned int c = 0; c < components; ++c)
          {
            auto& row = partners[from.nodes.dofs[j * from.nodes.components + c]];
            for (const auto& [l, m] : M[j])
              if (std::abs(m) > 1e-12 * D[j])
                row.emplace_back(to.nodes.dofs[l * to.nodes.components + c], m / D[j]);
          }
      }
    return partners;
  }

  template InterfaceFaces<2> gather_interface_faces<2>(const DoFHandler<2>&, unsigned int,
                                                       const std::function<bool(types::boundary_id)>&,
                                                       MPI_Comm);
  template InterfaceFaces<3> gather_interface_faces<3>(const DoFHandler<3>&, unsigned int,
                                                       const std::function<bool(types::boundary_id)>&,
                                                       MPI_Comm);
  template InterfacePartners dual_mortar_partners<2>(const InterfaceFaces<2>&, const InterfaceFaces<2>&,
                                                     unsigned int, const std::string&);
  template InterfacePartners dual_mortar_partners<3>(const InterfaceFaces<3>&, const InterfaceFaces<3>&,
                                                     unsigned int, const std::string&);
} // namespace physics::fsi
