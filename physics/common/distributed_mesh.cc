#include "common/distributed_mesh.h"

#include "common/mesh_input.h"
#include "common/row_exchange.h"

#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria_description.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/vector_tools.h>

#include <metis.h>

#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>

namespace physics
{
  namespace
  {
    /// The group size deal.II's construction in groups uses: `requested`, or for 0 the number
    /// of ranks of the smallest compute node (ranks sharing memory), so that every node has one
    /// group root where ranks are placed node by node.
    unsigned int resolved_group_size(MPI_Comm comm, unsigned int requested)
    {
      if (requested > 0)
        return requested;
      MPI_Comm node;
      MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
      int ranks_on_node = 1;
      MPI_Comm_size(node, &ranks_on_node);
      MPI_Comm_free(&node);
      return dealii::Utilities::MPI::min(static_cast<unsigned int>(ranks_on_node), comm);
    }

    bool is_group_root(MPI_Comm comm, unsigned int group_size)
    {
      return dealii::Utilities::MPI::this_mpi_process(comm) % group_size == 0;
    }

    /// METIS's parts of the active cells of `tria` on the cells' face graph, balancing the cell
    /// count and, where `is_marked` is given (one flag per active cell), the marked cells too
    /// (two constraints).
    ///
    /// The imbalance METIS may accept is 3 % over the average part (METIS_OPTION_UFACTOR 30, the
    /// default of its k-way partitioning), also for the recursive bisection used for few parts,
    /// whose default is 0.1 % (there the tolerance applies to each of the log2(parts) bisections
    /// and compounds: each gets its share of the 3 %). With 0.1 % a cut cannot follow a layer of
    /// cells unless that layer happens to halve the mesh within one cell in a thousand: on the
    /// pressure-wave tube at refinement 4 (80 layers of cells along the axis) METIS cut the fluid
    /// at 2 ranks through three layers, jagged, with 37 % more rows coupled to the other rank
    /// than a cut along one layer, and the fluid's rank-local ILU(0) in the FSI preconditioner
    /// lost an iteration of GMRES for it (6.4 instead of 5.6 per Newton step, the 1-rank count).
    template <int dim>
    std::vector<idx_t> metis_parts(const dealii::Triangulation<dim>& tria, unsigned int n_parts,
                                   const std::vector<char>& is_marked)
    {
      const unsigned int             n_cells = tria.n_active_cells();
      const idx_t                    n_constraints = is_marked.empty() ? 1 : 2;
      dealii::DynamicSparsityPattern graph;
      dealii::GridTools::get_face_connectivity_of_cells(tria, graph);
      std::vector<idx_t> row_start{0}, neighbours, weights;
      row_start.reserve(n_cells + 1);
      weights.reserve(n_constraints * n_cells);
      for (unsigned int i = 0; i < n_cells; ++i)
        {
          for (auto entry = graph.begin(i); entry != graph.end(i); ++entry)
            if (entry->column() != i)
              neighbours.push_back(static_cast<idx_t>(entry->column()));
          row_start.push_back(static_cast<idx_t>(neighbours.size()));
          weights.push_back(1);
          if (n_constraints == 2)
            weights.push_back(is_marked[i]);
        }
      idx_t n_vertices = n_cells, constraints = n_constraints, parts = n_parts, edge_cut = 0;
      idx_t options[METIS_NOPTIONS];
      METIS_SetDefaultOptions(options);
      // Recursive bisection for few parts, k-way beyond, as deal.II's METIS partition chooses.
      const bool   bisection        = n_parts <= 8;
      const double levels           = bisection ? std::ceil(std::log2(static_cast<double>(n_parts))) : 1;
      options[METIS_OPTION_UFACTOR] = static_cast<idx_t>(30 / levels);
      std::vector<idx_t> metis_part(n_cells);
      const auto         partition = bisection ? METIS_PartGraphRecursive : METIS_PartGraphKway;
      const int          status =
          partition(&n_vertices, &constraints, row_start.data(), neighbours.data(), weights.data(), nullptr,
                    nullptr, &parts, nullptr, nullptr, options, &edge_cut, metis_part.data());
      if (status != METIS_OK)
        throw std::runtime_error("METIS could not partition the mesh into " + std::to_string(n_parts) +
                                 " parts (status " + std::to_string(status) + ")");
      return metis_part;
    }
  } // namespace

  template <int dim>
  std::vector<unsigned int> partition_with_two_balances(dealii::Triangulation<dim>& tria,
                                                        unsigned int n_parts, const CellMarker<dim>& marked)
  {
    const unsigned int n_cells = tria.n_active_cells();
    std::vector<char>  is_marked(n_cells, 0);
    unsigned int       n_marked = 0;
    if (marked)
      for (const auto& cell : tria.active_cell_iterators())
        if (marked(cell))
          {
            is_marked[cell->active_cell_index()] = 1;
            ++n_marked;
          }

    if (n_parts == 1)
      for (const auto& cell : tria.active_cell_iterators())
        cell->set_subdomain_id(0);
    else
      {
        const std::vector<idx_t> part =
            metis_parts(tria, n_parts, n_marked < n_parts ? std::vector<char>() : is_marked);
        for (const auto& cell : tria.active_cell_iterators())
          cell->set_subdomain_id(part[cell->active_cell_index()]);
      }

    std::vector<unsigned int> marked_per_part(n_parts, 0);
    for (const auto& cell : tria.active_cell_iterators())
      marked_per_part[cell->subdomain_id()] += is_marked[cell->active_cell_index()];
    return marked_per_part;
  }

  template <int dim>
  void create_distributed_mesh(dealii::parallel::fullydistributed::Triangulation<dim>& tria,
                               const std::function<void(dealii::Triangulation<dim>&)>& serial_mesh,
                               unsigned int group_size, const CellMarker<dim>& balanced,
                               const PartitionHook<dim>& after_partition)
  {
    const MPI_Comm comm = tria.get_communicator();
    group_size          = resolved_group_size(comm, group_size);

    // The serial mesh is built before deal.II's collective construction starts, so that a bad
    // input stops every rank with the root's message instead of leaving the others waiting.
    std::unique_ptr<dealii::Triangulation<dim>> serial;
    std::string                                 error;
    if (is_group_root(comm, group_size))
      try
        {
          serial = std::make_unique<dealii::Triangulation<dim>>();
          serial_mesh(*serial);
        }
      catch (const std::invalid_argument& e)
        {
          error = e.what();
        }
    throw_if_any_rank_failed(error, comm);

    const auto description =
        dealii::TriangulationDescription::Utilities::create_description_from_triangulation_in_groups<dim,
                                                                                                     dim>(
            [&](dealii::Triangulation<dim>& t) { t = std::move(*serial); },
            [&](dealii::Triangulation<dim>& t, const MPI_Comm& c, unsigned int) {
              // METIS on the cell graph: parts of equal size (within 3 %) with short
              // interfaces; with equal shares of the marked cells too where the caller marks some.
              partition_with_two_balances(t, dealii::Utilities::MPI::n_mpi_processes(c), balanced);
              if (after_partition)
                after_partition(t);
            },
            comm, static_cast<int>(group_size));
    serial.reset();
    tria.create_triangulation(description);
  }

  template <int dim>
  void read_distributed_mesh(const std::string& file, const GmshSource& gmsh, int global_refinements,
                             const std::string&                                      work_directory,
                             dealii::parallel::fullydistributed::Triangulation<dim>& tria,
                             const CellMarker<dim>&                                  balanced)
  {
    const MPI_Comm     comm       = tria.get_communicator();
    const unsigned int group_size = resolved_group_size(comm, 0);
    // gmsh runs once (on rank 0); its mesh goes to the group roots only.
    MPI_Comm roots;
    MPI_Comm_split(comm, is_group_root(comm, group_size) ? 0 : MPI_UNDEFINED, 0, &roots);
    try
      {
        create_distributed_mesh<dim>(
            tria,
            [&](dealii::Triangulation<dim>& serial) {
              read_mesh(file, gmsh, work_directory, serial, roots);
              serial.refine_global(global_refinements);
            },
            group_size, balanced);
      }
    catch (...)
      {
        if (roots != MPI_COMM_NULL)
          MPI_Comm_free(&roots);
        throw;
      }
    if (roots != MPI_COMM_NULL)
      MPI_Comm_free(&roots);
  }

  template <int dim>
  void add_boundary_constraints(const dealii::DoFHandler<dim>& dof_handler, dealii::types::boundary_id id,
                                const dealii::Function<dim>& g, dealii::AffineConstraints<double>& constraints,
                                const dealii::ComponentMask& mask)
  {
    std::map<dealii::types::global_dof_index, double> values;
    dealii::VectorTools::interpolate_boundary_values(dof_handler, id, g, values, mask);
    const auto& owned = dof_handler.locally_owned_dofs();
    for (const auto& [dof, value] : values)
      if (owned.is_element(dof) && !constraints.is_constrained(dof))
        {
          constraints.add_line(dof);
          constraints.set_inhomogeneity(dof, value);
        }
  }

  template <int dim>
  void close_distributed_constraints(const dealii::DoFHandler<dim>& dof_handler, const dealii::IndexSet& known,
                                     dealii::AffineConstraints<double>& constraints)
  {
    constraints.make_consistent_in_parallel(dof_handler.locally_owned_dofs(), known,
                                            dof_handler.get_triangulation().get_communicator());
    constraints.close();
  }

  template <int dim>
  std::vector<double> owned_vertex_positions(const dealii::DoFHandler<dim>& dof_handler,
                                             const dealii::IndexSet&        owned,
                                             const std::function<bool(dealii::types::global_dof_index)>& keep)
  {
    std::map<dealii::types::global_dof_index, dealii::Point<dim>> vertex_of_dof;
    for (const auto& cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        for (const unsigned v : cell->vertex_indices())
          {
            const auto dof = cell->vertex_dof_index(v, 0);
            if (owned.is_element(dof) && keep(dof))
              vertex_of_dof[dof] = cell->vertex(v);
          }
    std::vector<double> xyz;
    xyz.reserve(dim * vertex_of_dof.size());
    for (const auto& [dof, x] : vertex_of_dof)
      for (unsigned c = 0; c < dim; ++c)
        xyz.push_back(x[c]);
    return xyz;
  }

  template void create_distributed_mesh<2>(dealii::parallel::fullydistributed::Triangulation<2>&,
                                           const std::function<void(dealii::Triangulation<2>&)>&,
                                           unsigned int, const CellMarker<2>&, const PartitionHook<2>&);
  template void create_distributed_mesh<3>(dealii::parallel::fullydistributed::Triangulation<3>&,
                                           const std::function<void(dealii::Triangulation<3>&)>&,
                                           unsigned int, const CellMarker<3>&, const PartitionHook<3>&);
  template std::vector<unsigned int> partition_with_two_balances<2>(dealii::Triangulation<2>&, unsigned int,
                                                                    const CellMarker<2>&);
  template std::vector<unsigned int> partition_with_two_balances<3>(dealii::Triangulation<3>&, unsigned int,
                                                                    const CellMarker<3>&);
  template void add_boundary_constraints<2>(const dealii::DoFHandler<2>&, dealii::types::boundary_id,
                                            const dealii::Function<2>&, dealii::AffineConstraints<double>&,
                                            const dealii::ComponentMask&);
  template void add_boundary_constraints<3>(const dealii::DoFHandler<3>&, dealii::types::boundary_id,
                                            const dealii::Function<3>&, dealii::AffineConstraints<double>&,
                                            const dealii::ComponentMask&);
  template void close_distributed_constraints<2>(const dealii::DoFHandler<2>&, const dealii::IndexSet&,
                                                 dealii::AffineConstraints<double>&);
  template void close_distributed_constraints<3>(const dealii::DoFHandler<3>&, const dealii::IndexSet&,
                                                 dealii::AffineConstraints<double>&);
  template void read_distributed_mesh<2>(const std::string&, const GmshSource&, int, const std::string&,
                                         dealii::parallel::fullydistributed::Triangulation<2>&,
                                         const CellMarker<2>&);
  template void read_distributed_mesh<3>(const std::string&, const GmshSource&, int, const std::string&,
                                         dealii::parallel::fullydistributed::Triangulation<3>&,
                                         const CellMarker<3>&);
  template std::vector<double>
  owned_vertex_positions<2>(const dealii::DoFHandler<2>&, const dealii::IndexSet&,
                            const std::function<bool(dealii::types::global_dof_index)>&);
  template std::vector<double>
  owned_vertex_positions<3>(const dealii::DoFHandler<3>&, const dealii::IndexSet&,
                            const std::function<bool(dealii::types::global_dof_index)>&);
} // namespace physics
