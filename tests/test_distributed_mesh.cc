// Fully distributed meshes (physics/common/distributed_mesh.h): no rank stores the whole mesh
// when there are several, the parts add up to it, Dirichlet constraints on every stored DOF are
// exactly those of the serial mesh (a fully distributed triangulation shows the outer faces of
// its ghost layer as boundary faces with id 0; deal.II's interpolate_boundary_values alone would
// constrain the ghost DOFs there), and a bad mesh file stops every rank with the same one-line
// message instead of leaving the ranks that do not read it waiting. ctest runs it on 1 and 2
// ranks (the storage test is only meaningful on 2).
#include "common/distributed_mesh.h"
#include "common/mesh_input.h"
#include "common/solid_mechanics.h"
#include "fsi/fsi_meshes.h"
#include "fsi/interface_nodes.h"

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

using namespace dealii;

namespace
{
  /// A 6 x 5 x 4 box with boundary ids 0..5 (face x = 0 has id 0), fully distributed.
  void make_box(parallel::fullydistributed::Triangulation<3>& tria)
  {
    physics::create_distributed_mesh<3>(tria, [](Triangulation<3>& box) {
      GridGenerator::subdivided_hyper_rectangle(box, {6, 5, 4}, Point<3>(), Point<3>(1.2, 1.0, 0.8), true);
    });
  }
} // namespace

TEST(DistributedMesh, EveryRankStoresOnlyItsPartAndTheGhostLayer)
{
  const MPI_Comm                               comm = MPI_COMM_WORLD;
  parallel::fullydistributed::Triangulation<3> tria(comm);
  make_box(tria);
  EXPECT_EQ(tria.n_global_active_cells(), 120u);
  EXPECT_EQ(Utilities::MPI::sum(tria.n_locally_owned_active_cells(), comm), 120u);
  if (Utilities::MPI::n_mpi_processes(comm) > 1)
    {
      // METIS parts of equal size, and far fewer cells stored than the whole mesh.
      EXPECT_LT(tria.n_active_cells(), tria.n_global_active_cells());
      EXPECT_GE(tria.n_locally_owned_active_cells(), 120u / Utilities::MPI::n_mpi_processes(comm) - 6);
    }
}

TEST(DistributedMesh, BoundaryConstraintsAreThoseOfTheSerialMesh)
{
  const MPI_Comm                               comm = MPI_COMM_WORLD;
  parallel::fullydistributed::Triangulation<3> tria(comm);
  make_box(tria);
  const FESystem<3> fe(FE_Q<3>(1), 3);
  DoFHandler<3>     dof_handler(tria);
  dof_handler.distribute_dofs(fe);
  IndexSet relevant;
  DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);

  AffineConstraints<double> constraints(relevant);
  physics::add_boundary_constraints(dof_handler, 0, Functions::ConstantFunction<3>(0.25, 3), constraints);
  physics::close_distributed_constraints(dof_handler, relevant, constraints);

  // Every stored DOF: constrained exactly when its vertex lies on x = 0, with the value there.
  unsigned int wrong = 0, owned_constrained = 0;
  for (const auto& cell : dof_handler.active_cell_iterators())
    if (!cell->is_artificial())
      for (const unsigned int v : cell->vertex_indices())
        for (unsigned int c = 0; c < 3; ++c)
          {
            const auto dof       = cell->vertex_dof_index(v, c);
            const bool on_face   = std::abs(cell->vertex(v)[0]) < 1e-12;
            const bool is_constr = constraints.is_constrained(dof);
            if (is_constr != on_face || (is_constr && constraints.get_inhomogeneity(dof) != 0.25))
              ++wrong;
          }
  for (const auto dof : dof_handler.locally_owned_dofs())
    owned_constrained += constraints.is_constrained(dof);
  EXPECT_EQ(Utilities::MPI::sum(wrong, comm), 0u);
  EXPECT_EQ(Utilities::MPI::sum(owned_constrained, comm), 3u * 6 * 5); // 6 x 5 vertices on x = 0
}

TEST(DistributedMesh, AMissingMeshFileStopsEveryRankWithOneMessage)
{
  parallel::fullydistributed::Triangulation<2> tria(MPI_COMM_WORLD);
  try
    {
      physics::read_distributed_mesh<2>("/nonexistent/mesh.msh", 1, 0, TEST_OUTPUT_DIR, tria);
      FAIL() << "no exception";
    }
  catch (const std::invalid_argument& e)
    {
      EXPECT_EQ(std::string(e.what()), "/nonexistent/mesh.msh: mesh file not found (parameter 'Mesh file')");
    }
}

TEST(DistributedMesh, AGmshSourceIsMeshedOnceAndRefinedBeforePartitioning)
{
  parallel::fullydistributed::Triangulation<2> coarse(MPI_COMM_WORLD), fine(MPI_COMM_WORLD);
  const std::string                            geo = std::string(MESH_DIR) + "/two_blocks_2d.geo";
  physics::read_distributed_mesh<2>(geo, 1, 0, TEST_OUTPUT_DIR, coarse);
  physics::read_distributed_mesh<2>(geo, 1, 1, TEST_OUTPUT_DIR, fine);
  EXPECT_GT(coarse.n_global_active_cells(), 0u);
  EXPECT_EQ(fine.n_global_active_cells(), 4 * coarse.n_global_active_cells());
}

// A Gmsh variable must occur in the .geo's code: a name that only a comment or a string
// mentions would be defined by gmsh and never used.
TEST(DistributedMesh, AGmshVariableMustOccurInTheGeoCode)
{
  physics::GmshSource source;
  source.variables = {{"length", 20.0}};
  const auto check = [&](const std::string& geo) { source.check_variables_in("test.geo", geo); };
  EXPECT_NO_THROW(check("DefineConstant[ length = 10 ];\nPoint(1) = {length, 0, 0};"));
  EXPECT_NO_THROW(check("// the bar\nl = length; /* a comment */"));
  EXPECT_THROW(check("// length: the bar's length\nl = 10;"), std::invalid_argument);
  EXPECT_THROW(check("/* length\n of the bar */ l = 10;"), std::invalid_argument);
  EXPECT_THROW(check("Printf(\"length\");"), std::invalid_argument);
  EXPECT_THROW(check("lengths = 10; bar_length = 2;"), std::invalid_argument);
  EXPECT_THROW(check("l = 10; /* length"), std::invalid_argument); // unterminated comment
}

namespace
{
  /// A 16 x 4 x 4 bar whose end face x = 16 (boundary id 1) stands for a contact surface: a
  /// partition by cell count alone cuts the bar across, which leaves that face on one part.
  void make_bar(Triangulation<3>& bar)
  {
    GridGenerator::subdivided_hyper_rectangle(bar, {16, 4, 4}, Point<3>(), Point<3>(16, 4, 4), true);
  }

  bool at_end_face(const Triangulation<3>::active_cell_iterator& cell)
  {
    for (const unsigned int f : cell->face_indices())
      if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == 1)
        return true;
    return false;
  }
} // namespace

// The partition with two balances: every part gets its share of the 16 marked cells and of all
// 256 cells, where the partition by cell count alone puts all marked cells on one of two parts.
TEST(DistributedMesh, PartitionGivesEveryPartItsShareOfTheMarkedCells)
{
  Triangulation<3> bar;
  make_bar(bar);
  const auto plain = physics::partition_with_two_balances<3>(bar, 2, {});
  EXPECT_EQ(plain[0] + plain[1], 0u); // nothing marked, nothing counted
  unsigned int on_part_0 = 0;
  for (const auto& cell : bar.active_cell_iterators())
    on_part_0 += at_end_face(cell) && cell->subdomain_id() == 0;
  EXPECT_TRUE(on_part_0 == 0 || on_part_0 == 16)
      << on_part_0 << " of 16 marked cells on part 0 by cell count alone";

  for (const unsigned int n_parts : {2u, 3u, 4u})
    {
      const auto                marked = physics::partition_with_two_balances<3>(bar, n_parts, at_end_face);
      std::vector<unsigned int> cells(n_parts, 0), counted(n_parts, 0);
      for (const auto& cell : bar.active_cell_iterators())
        {
          ASSERT_LT(cell->subdomain_id(), n_parts);
          ++cells[cell->subdomain_id()];
          counted[cell->subdomain_id()] += at_end_face(cell);
        }
      for (unsigned int p = 0; p < n_parts; ++p)
        {
          EXPECT_EQ(marked[p], counted[p]);
          // METIS's default tolerance is 3 % over the average; one cell more for the rounding.
          EXPECT_LE(cells[p], 1.03 * 256 / n_parts + 1) << n_parts << " parts, part " << p;
          EXPECT_GE(marked[p], 16 / n_parts - 2) << n_parts << " parts, part " << p;
          EXPECT_LE(marked[p], (16 + n_parts - 1) / n_parts + 2) << n_parts << " parts, part " << p;
        }
    }
}

// The same through the fully distributed mesh: on 2 ranks each owns marked cells.
TEST(DistributedMesh, DistributedMeshBalancesTheMarkedCells)
{
  const MPI_Comm                               comm = MPI_COMM_WORLD;
  parallel::fullydistributed::Triangulation<3> tria(comm);
  physics::create_distributed_mesh<3>(tria, make_bar, 0, at_end_face);
  unsigned int owned_marked = 0;
  for (const auto& cell : tria.active_cell_iterators())
    owned_marked += cell->is_locally_owned() && at_end_face(cell);
  EXPECT_EQ(Utilities::MPI::sum(owned_marked, comm), 16u);
  const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);
  EXPECT_GE(owned_marked, 16 / n_ranks - 2);
  EXPECT_LE(Utilities::MPI::max(tria.n_locally_owned_active_cells(), comm), 1.03 * 256 / n_ranks + 1);
}

// An element that inverts in the cells of one rank only: every rank leaves the assembly with the
// same std::domain_error (before, the rank that found it left while the others waited in the
// matrix compress, and the next collective hung: the collapsing rings on 2 ranks).
TEST(DistributedMesh, InvertedElementOnOneRankStopsTheAssemblyEverywhere)
{
  const MPI_Comm                               comm = MPI_COMM_WORLD;
  const unsigned int                           last = Utilities::MPI::n_mpi_processes(comm) - 1;
  parallel::fullydistributed::Triangulation<3> tria(comm);
  make_box(tria);
  const FESystem<3> fe(FE_Q<3>(1), 3);
  DoFHandler<3>     dof_handler(tria);
  dof_handler.distribute_dofs(fe);
  const IndexSet owned = dof_handler.locally_owned_dofs();
  IndexSet       relevant;
  DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);

  physics::SolidModel<3> model;
  const std::shared_ptr<const physics::HyperelasticMaterial<3>> law =
      physics::make_material<3>("NeoHooke", physics::LameParameters::from_young_poisson(1.0, 0.3));
  for (const auto& cell : tria.active_cell_iterators())
    model.materials[cell->material_id()] = law;
  // The last rank pushes one vertex of its first cell through the opposite face (2 cell sizes in x).
  TrilinosWrappers::MPI::Vector u_owned(owned, comm);
  std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
  if (Utilities::MPI::this_mpi_process(comm) == last)
    for (const auto& cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          const types::global_dof_index x_dof = dofs[fe.component_to_system_index(0, 0)];
          if (owned.is_element(x_dof))
            {
              u_owned[x_dof] = 0.4;
              break;
            }
        }
  u_owned.compress(VectorOperation::insert);
  TrilinosWrappers::MPI::Vector u(owned, relevant, comm);
  u = u_owned;

  DynamicSparsityPattern pattern(relevant);
  DoFTools::make_sparsity_pattern(dof_handler, pattern);
  SparsityTools::distribute_sparsity_pattern(pattern, owned, comm, relevant);
  TrilinosWrappers::SparseMatrix K;
  K.reinit(owned, owned, pattern, comm);
  TrilinosWrappers::MPI::Vector residual(owned, comm);
  AffineConstraints<double>     none;
  std::string                   message;
  try
    {
      physics::assemble_solid(dof_handler, model, u, none, residual, &K);
    }
  catch (const std::domain_error& e)
    {
      message = e.what();
    }
  EXPECT_NE(message.find("det F"), std::string::npos) << "rank " << Utilities::MPI::this_mpi_process(comm);
  // Every rank got the same message, and the communicator still works.
  EXPECT_EQ(Utilities::MPI::max(static_cast<int>(message.size()), comm), static_cast<int>(message.size()));
}

// The FSI meshes (fsi/fsi_meshes.h) are partitioned each on its own; the structure's parts are
// then numbered after the fluid's. renumbering_by_overlap: the permutation that keeps the most
// shared interface faces on one rank.
TEST(FsiMeshes, RenumberingByOverlapKeepsTheMostInterfaceFacesOnOneRank)
{
  using physics::fsi::renumbering_by_overlap;
  // Two parts the wrong way round (the tube at 2 ranks before): swapped.
  EXPECT_EQ(renumbering_by_overlap({{0, 90}, {88, 2}}), (std::vector<unsigned int>{1, 0}));
  // Already aligned: unchanged.
  EXPECT_EQ(renumbering_by_overlap({{50, 3}, {1, 40}}), (std::vector<unsigned int>{0, 1}));
  // Part 0 meets fluid parts 1 and 2, part 1 mostly 2: the largest count (part 1 -> 2) first,
  // part 0 then takes 1, part 2 (no interface) the number left over.
  EXPECT_EQ(renumbering_by_overlap({{0, 30, 20}, {0, 0, 40}, {0, 0, 0}}),
            (std::vector<unsigned int>{1, 2, 0}));
  // A permutation in every case, ties by part number.
  EXPECT_EQ(renumbering_by_overlap({{5, 5, 5}, {5, 5, 5}, {5, 5, 5}}), (std::vector<unsigned int>{0, 1, 2}));
  EXPECT_THROW(renumbering_by_overlap({{1, 2}, {3}}), std::logic_error);
}

namespace
{
  /// The share of the structure's owned interface faces whose fluid face (same centre) is owned by
  /// the same rank, over all ranks.
  template <int dim>
  double interface_faces_on_one_rank(const parallel::fullydistributed::Triangulation<dim>& fluid,
                                     const parallel::fullydistributed::Triangulation<dim>& structure)
  {
    // the tube is a few centimetres long, its cells millimetres
    auto key = [](const Point<dim>& x) { return physics::fsi::position_key(x, 1e-9); };
    std::set<physics::fsi::PositionKey<dim>> fluid_faces;
    for (const auto& cell : fluid.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned f : cell->face_indices())
          if (cell->at_boundary(f) && cell->face(f)->boundary_id() == physics::fsi::boundary::interface)
            fluid_faces.insert(key(cell->face(f)->center()));
    double same = 0, all = 0;
    for (const auto& cell : structure.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned f : cell->face_indices())
          if (cell->at_boundary(f) && cell->face(f)->boundary_id() == physics::fsi::boundary::interface)
            {
              ++all;
              same += fluid_faces.count(key(cell->face(f)->center()));
            }
    return Utilities::MPI::sum(same, MPI_COMM_WORLD) / Utilities::MPI::sum(all, MPI_COMM_WORLD);
  }
} // namespace

// On the pressure-wave tube (meshes/fsi_tube_3d.geo at refinement 1) the structure's part k lies
// around the fluid's part k: at least 90 % of the interface faces have both sides on one rank
// (measured: 1 / 0.956 / 1 on 2 / 3 / 4 ranks). METIS alone, numbering the two meshes' parts on
// their own: 1 / 0.31 / 0.5 (and at refinement 4 on 2 ranks none: the halves the other way round).
TEST(FsiMeshes, TheStructuresPartsLieAroundTheFluidsParts)
{
  parallel::fullydistributed::Triangulation<3> fluid(MPI_COMM_WORLD), structure(MPI_COMM_WORLD);
  physics::fsi::read_fsi_meshes<3>(std::string(MESH_DIR) + "/fsi_tube_3d.geo", 1, 0, TEST_OUTPUT_DIR, fluid,
                                   structure);
  const double share = interface_faces_on_one_rank(fluid, structure);
  std::cout << "tube, " << Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD)
            << " ranks: interface faces with both sides on one rank " << share << "\n";
  EXPECT_GE(share, Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) == 1 ? 1.0 : 0.9);
}
