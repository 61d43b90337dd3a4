#include "fsi/fsi_meshes.h"

#include "common/distributed_mesh.h"
#include "common/mesh_input.h"
#include "fsi/interface_nodes.h"

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>

namespace physics::fsi
{
  using namespace dealii;

  std::vector<unsigned int> renumbering_by_overlap(const std::vector<std::vector<unsigned int>>& overlap)
  {
    const unsigned int n = overlap.size();
    // (count, structure part, fluid part), largest counts first; ties by part numbers, so that
    // every group root computes the same renumbering.
    std::vector<std::tuple<unsigned int, unsigned int, unsigned int>> shared;
    for (unsigned int s = 0; s < n; ++s)
      {
        if (overlap[s].size() != n)
          throw std::logic_error("renumbering_by_overlap: the overlap matrix is not square");
        for (unsigned int f = 0; f < n; ++f)
          if (overlap[s][f] > 0)
            shared.emplace_back(overlap[s][f], s, f);
      }
    std::sort(shared.begin(), shared.end(), [](const auto& a, const auto& b) {
      return std::get<0>(a) != std::get<0>(b) ? std::get<0>(a) > std::get<0>(b) : a < b;
    });
    const unsigned int        none = numbers::invalid_unsigned_int;
    std::vector<unsigned int> number(n, none);
    std::vector<char>         taken(n, 0);
    for (const auto& [count, s, f] : shared)
      if (number[s] == none && !taken[f])
        {
          number[s] = f;
          taken[f]  = 1;
        }
    unsigned int next = 0;
    for (auto& k : number)
      if (k == none)
        {
          while (taken[next])
            ++next;
          k           = next;
          taken[next] = 1;
        }
    return number;
  }

  namespace
  {
    /// METIS partitions the fluid and the structure meshes on their own, and nothing makes its
    /// part k of the structure lie where its part k of the fluid does: on the pressure-wave tube
    /// at refinement 4 and 2 ranks it put the structure's part 0 around the fluid's part 1, so
    /// that every coupling of the condensed interface (a fluid interface DOF's row of structure
    /// DOFs) joined two ranks, and so did the structure/fluid coupling blocks of the Newton
    /// system and of every AMG level. The fluid's hook records the part of each interface face;
    /// the structure's renumbers its parts after them (renumbering_by_overlap). Both run on
    /// every group root, the fluid's first. The app prints the share of the couplings on one rank.
    template <int dim>
    class InterfacePartition
    {
    public:
      PartitionHook<dim> record_fluid()
      {
        return [this](Triangulation<dim>& fluid) {
          tolerance_ = 1e-9 * GridTools::diameter(fluid);
          fluid_part_.clear();
          for (const auto& cell : fluid.active_cell_iterators())
            for (const unsigned f : cell->face_indices())
              if (cell->at_boundary(f) && cell->face(f)->boundary_id() == boundary::interface)
                fluid_part_[position_key(cell->face(f)->center(), tolerance_)] = cell->subdomain_id();
        };
      }

      PartitionHook<dim> follow_fluid() const
      {
        return [this](Triangulation<dim>& structure) {
          unsigned int n = 0;
          for (const auto& cell : structure.active_cell_iterators())
            n = std::max<unsigned int>(n, cell->subdomain_id() + 1);
          for (const auto& [key, part] : fluid_part_)
            n = std::max<unsigned int>(n, part + 1);
          std::vector<std::vector<unsigned int>> overlap(n, std::vector<unsigned int>(n, 0));
          for (const auto& cell : structure.active_cell_iterators())
            for (const unsigned f : cell->face_indices())
              if (cell->at_boundary(f) && cell->face(f)->boundary_id() == boundary::interface)
                {
                  const auto it = fluid_part_.find(position_key(cell->face(f)->center(), tolerance_));
                  if (it != fluid_part_.end())
                    ++overlap[cell->subdomain_id()][it->second];
                }
          const auto number = renumbering_by_overlap(overlap);
          for (const auto& cell : structure.active_cell_iterators())
            cell->set_subdomain_id(number[cell->subdomain_id()]);
        };
      }

    private:
      double                                                    tolerance_ = 0;
      std::map<PositionKey<dim>, types::subdomain_id>           fluid_part_;
    };
  } // namespace

  void make_channel_meshes(const ChannelGeometry& g, parallel::fullydistributed::Triangulation<2>& fluid,
                           parallel::fullydistributed::Triangulation<2>& structure)
  {
    // Faces by position: the planes x = 0 and x = L, the interface lines y = 0 and y = H.
    const double tol      = 1e-9 * g.length;
    auto         classify = [&](Triangulation<2>& tria) {
      for (const auto& cell : tria.active_cell_iterators())
        {
          cell->set_material_id(0);
          for (const unsigned f : cell->face_indices())
            if (cell->at_boundary(f))
              {
                const Point<2> c = cell->face(f)->center();
                cell->face(f)->set_boundary_id(std::abs(c[0]) < tol                 ? boundary::inlet
                                               : std::abs(c[0] - g.length) < tol     ? boundary::outlet
                                               : std::abs(c[1]) < tol                ? boundary::interface
                                               : std::abs(c[1] - g.height) < tol     ? boundary::interface
                                                                                     : boundary::outer);
              }
        }
    };
    const unsigned        nx = g.cells_x;
    InterfacePartition<2> parts;
    create_distributed_mesh<2>(
        fluid,
        [&](Triangulation<2>& tria) {
          GridGenerator::subdivided_hyper_rectangle(tria, {nx, g.cells_fluid}, Point<2>(),
                                                    Point<2>(g.length, g.height));
          classify(tria);
        },
        0, {}, parts.record_fluid());
    create_distributed_mesh<2>(
        structure,
        [&](Triangulation<2>& tria) {
          Triangulation<2> lower, upper;
          const unsigned   nxw = g.cells_wall_x > 0 ? g.cells_wall_x : nx;
          GridGenerator::subdivided_hyper_rectangle(lower, {nxw, g.cells_wall},
                                                    Point<2>(0, -g.wall_thickness), Point<2>(g.length, 0));
          GridGenerator::subdivided_hyper_rectangle(upper, {nxw, g.cells_wall}, Point<2>(0, g.height),
                                                    Point<2>(g.length, g.height + g.wall_thickness));
          GridGenerator::merge_triangulations(lower, upper, tria);
          classify(tria);
        },
        0, {}, parts.follow_fluid());
  }

  namespace
  {
    /// The cells of `whole` with material id `material` as a triangulation of their own: boundary
    /// faces of `whole` keep their ids, faces `whole` had between the two parts become the interface.
    template <int dim>
    void extract_part(const Triangulation<dim>& whole, types::material_id material, Triangulation<dim>& part,
                      const std::string& file)
    {
      const std::string what = material == 1 ? "fluid (physical volume 1)" : "structure (physical volume 2)";
      std::set<typename Triangulation<dim>::active_cell_iterator> others;
      for (const auto& cell : whole.active_cell_iterators())
        {
          if (cell->material_id() != 1 && cell->material_id() != 2)
            throw std::invalid_argument("Mesh file '" + file + "': material id " +
                                        std::to_string(cell->material_id()) +
                                        " found; expected 1 (fluid) and 2 (structure) only");
          if (cell->material_id() != material)
            others.insert(cell);
        }
      if (others.size() == whole.n_active_cells())
        throw std::invalid_argument("Mesh file '" + file + "': no cell of the " + what);

      // Boundary faces of the whole mesh by their centres (in units of a tolerance far below
      // any cell size, so that the same face gives the same key in both meshes).
      const double tol = 1e-9 * GridTools::diameter(whole);
      auto         key = [tol](const Point<dim>& x) { return position_key(x, tol); };
      std::map<PositionKey<dim>, types::boundary_id> outer_faces;
      for (const auto& cell : whole.active_cell_iterators())
        for (const unsigned f : cell->face_indices())
          if (cell->at_boundary(f))
            outer_faces[key(cell->face(f)->center())] = cell->face(f)->boundary_id();

      GridGenerator::create_triangulation_with_removed_cells(whole, others, part);
      unsigned int interface_faces = 0, inlet_faces = 0;
      for (const auto& cell : part.active_cell_iterators())
        {
          cell->set_material_id(0);
          for (const unsigned f : cell->face_indices())
            if (cell->at_boundary(f))
              {
                const auto it = outer_faces.find(key(cell->face(f)->center()));
                const auto id = it != outer_faces.end() ? it->second : boundary::interface;
                cell->face(f)->set_boundary_id(id);
                interface_faces += id == boundary::interface;
                inlet_faces += id == boundary::inlet;
              }
        }
      if (interface_faces == 0)
        throw std::invalid_argument("Mesh file '" + file + "': the " + what +
                                    " does not touch the other part (no interface faces)");
      if (material == 1 && inlet_faces == 0)
        throw std::invalid_argument("Mesh file '" + file + "': the fluid has no inlet faces (physical " +
                                    (dim == 3 ? std::string("surface") : std::string("line")) + " 1)");
    }
  } // namespace

  template <int dim>
  void read_fsi_meshes(const std::string& file, const GmshSource& gmsh, int global_refinements,
                       const std::string&                              work_directory,
                       parallel::fullydistributed::Triangulation<dim>& fluid,
                       parallel::fullydistributed::Triangulation<dim>& structure)
  {
    // Each group root meshes the file itself (its own gmsh run in a temporary directory of its
    // own, mesh_input.h), once per part: the tube's gmsh run takes well under a second.
    InterfacePartition<dim> parts;
    for (auto [tria, material] : {std::pair{&fluid, 1}, std::pair{&structure, 2}})
      create_distributed_mesh<dim>(
          *tria,
          [&, material = material](Triangulation<dim>& part) {
            Triangulation<dim> whole;
            read_mesh(file, gmsh, work_directory, whole, MPI_COMM_SELF);
            whole.refine_global(global_refinements);
            extract_part(whole, static_cast<types::material_id>(material), part, file);
          },
          0, {}, material == 1 ? parts.record_fluid() : parts.follow_fluid());
  }

  template void read_fsi_meshes<2>(const std::string&, const GmshSource&, int, const std::string&,
                                   parallel::fullydistributed::Triangulation<2>&,
                                   parallel::fullydistributed::Triangulation<2>&);
  template void read_fsi_meshes<3>(const std::string&, const GmshSource&, int, const std::string&,
                                   parallel::fullydistributed::Triangulation<3>&,
                                   parallel::fullydistributed::Triangulation<3>&);
} // namespace physics::fsi
