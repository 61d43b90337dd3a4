#include "fsi/fsi_meshes.h"

#include "common/distributed_mesh.h"
#include "common/mesh_input.h"

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>

#include <array>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

namespace physics::fsi
{
  using namespace dealii;

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
    const unsigned nx = g.cells_x;
    create_distributed_mesh<2>(fluid, [&](Triangulation<2>& tria) {
      GridGenerator::subdivided_hyper_rectangle(tria, {nx, g.cells_fluid}, Point<2>(),
                                                Point<2>(g.length, g.height));
      classify(tria);
    });
    create_distributed_mesh<2>(structure, [&](Triangulation<2>& tria) {
      Triangulation<2> lower, upper;
      const unsigned nxw = g.cells_wall_x > 0 ? g.cells_wall_x : nx;
      GridGenerator::subdivided_hyper_rectangle(lower, {nxw, g.cells_wall}, Point<2>(0, -g.wall_thickness),
                                                Point<2>(g.length, 0));
      GridGenerator::subdivided_hyper_rectangle(upper, {nxw, g.cells_wall}, Point<2>(0, g.height),
                                                Point<2>(g.length, g.height + g.wall_thickness));
      GridGenerator::merge_triangulations(lower, upper, tria);
      classify(tria);
    });
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
      using Key        = std::array<long long, dim>;
      auto key         = [tol](const Point<dim>& x) {
        Key k;
        for (unsigned int d = 0; d < dim; ++d)
          k[d] = std::llround(x[d] / tol);
        return k;
      };
      std::map<Key, types::boundary_id> outer_faces;
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
    for (auto [tria, material] : {std::pair{&fluid, 1}, std::pair{&structure, 2}})
      create_distributed_mesh<dim>(*tria, [&](Triangulation<dim>& part) {
        Triangulation<dim> whole;
        read_mesh(file, gmsh, work_directory, whole, MPI_COMM_SELF);
        whole.refine_global(global_refinements);
        extract_part(whole, static_cast<types::material_id>(material), part, file);
      });
  }

  template void read_fsi_meshes<2>(const std::string&, const GmshSource&, int, const std::string&,
                                   parallel::fullydistributed::Triangulation<2>&,
                                   parallel::fullydistributed::Triangulation<2>&);
  template void read_fsi_meshes<3>(const std::string&, const GmshSource&, int, const std::string&,
                                   parallel::fullydistributed::Triangulation<3>&,
                                   parallel::fullydistributed::Triangulation<3>&);
} // namespace physics::fsi
