#include "fsi/interface_nodes.h"

#include <deal.II/base/mpi.h>

#include <array>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

namespace physics::fsi
{
  using namespace dealii;

  template <int dim>
  InterfaceNodes<dim> gather_interface_nodes(const DoFHandler<dim>& dofs, unsigned int components,
                                             const std::function<bool(types::boundary_id)>& on_interface,
                                             MPI_Comm                                       comm)
  {
    // This rank's owned interface vertices: coordinates (dim per node) and DOFs (components
    // per node), flat so that the all-gather sends plain arrays.
    const IndexSet&          owned = dofs.locally_owned_dofs();
    std::set<GlobalIndex>    seen;
    std::vector<double>      x;
    std::vector<GlobalIndex> indices;
    for (const auto& cell : dofs.active_cell_iterators())
      if (!cell->is_artificial())
        for (const unsigned int f : cell->face_indices())
          if (cell->at_boundary(f) && on_interface(cell->face(f)->boundary_id()))
            for (const unsigned int v : cell->face(f)->vertex_indices())
              {
                const GlobalIndex first = cell->face(f)->vertex_dof_index(v, 0);
                if (!owned.is_element(first) || !seen.insert(first).second)
                  continue;
                for (unsigned int d = 0; d < dim; ++d)
                  x.push_back(cell->face(f)->vertex(v)[d]);
                for (unsigned int c = 0; c < components; ++c)
                  indices.push_back(cell->face(f)->vertex_dof_index(v, c));
              }
    InterfaceNodes<dim> all;
    all.components = components;
    for (const auto& part : Utilities::MPI::all_gather(comm, x))
      for (std::size_t k = 0; k + dim <= part.size(); k += dim)
        {
          Point<dim> p;
          for (unsigned int d = 0; d < dim; ++d)
            p[d] = part[k + d];
          all.positions.push_back(p);
        }
    for (const auto& part : Utilities::MPI::all_gather(comm, indices))
      all.dofs.insert(all.dofs.end(), part.begin(), part.end());
    return all;
  }

  template <int dim>
  std::map<GlobalIndex, GlobalIndex> match_interface_nodes(const InterfaceNodes<dim>& from,
                                                           const InterfaceNodes<dim>& to, double tolerance)
  {
    // Nodes keyed by their coordinates in units of the tolerance (position_key).
    auto key = [tolerance](const Point<dim>& x) { return position_key(x, tolerance); };
    std::map<PositionKey<dim>, std::size_t> node_of;
    for (std::size_t k = 0; k < to.positions.size(); ++k)
      node_of[key(to.positions[k])] = k;
    const unsigned int                 n = std::min(from.components, to.components);
    std::map<GlobalIndex, GlobalIndex> partner;
    for (std::size_t k = 0; k < from.positions.size(); ++k)
      {
        const auto it = node_of.find(key(from.positions[k]));
        if (it == node_of.end())
          throw std::invalid_argument("Geometry: a fluid interface node at " +
                                      Utilities::to_string(from.positions[k][0]) +
                                      " has no structure node (with Coupling/Interface = matching nodes the "
                                      "interface meshes must match; dual mortar couples non-matching ones)");
        for (unsigned int c = 0; c < n; ++c)
          partner[from.dofs[k * from.components + c]] = to.dofs[it->second * to.components + c];
      }
    return partner;
  }

  template InterfaceNodes<2>                  gather_interface_nodes<2>(const DoFHandler<2>&, unsigned int,
                                                       const std::function<bool(types::boundary_id)>&,
                                                       MPI_Comm);
  template InterfaceNodes<3>                  gather_interface_nodes<3>(const DoFHandler<3>&, unsigned int,
                                                       const std::function<bool(types::boundary_id)>&,
                                                       MPI_Comm);
  template std::map<GlobalIndex, GlobalIndex> match_interface_nodes<2>(const InterfaceNodes<2>&,
                                                                       const InterfaceNodes<2>&, double);
  template std::map<GlobalIndex, GlobalIndex> match_interface_nodes<3>(const InterfaceNodes<3>&,
                                                                       const InterfaceNodes<3>&, double);
} // namespace physics::fsi
