#include "contact/contact_block_system.h"

#include "common/row_exchange.h"
#include "common/tpetra_bridge.h"

#include <deal.II/base/mpi.h>

#include <Xpetra_MapFactory.hpp>
#include <Xpetra_MatrixFactory.hpp>
#include <Xpetra_MultiVectorFactory.hpp>

#include <Epetra_CrsMatrix.h>

#include <algorithm>
#include <numeric>

namespace physics::contact
{
  using namespace multigrid;

  template <int dim>
  ContactLinearSystem build_contact_system(MPI_Comm comm, const std::vector<OwnedNode<dim>>& nodes,
                                           const MortarContact<dim>& contact, const dealii::IndexSet& owned,
                                           const dealii::IndexSet& ghosts,
                                           const dealii::TrilinosWrappers::SparseMatrix& K,
                                           const dealii::TrilinosWrappers::MPI::Vector& residual,
                                           const RowPieces& rows, const std::map<GlobalIndex, double>& residual_pieces)
  {
    const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(comm);
    const unsigned int n_ranks = dealii::Utilities::MPI::n_mpi_processes(comm);
    const auto&        state = contact.state();
    const GlobalIndex  n_dofs = owned.size();

    // Class of every owned node; sort by (class, first DOF).
    auto class_of = [&](const OwnedNode<dim>& node) {
      if (node.slave_index >= 0)
        return state.active[node.slave_index] ? NodeClass::active : NodeClass::inactive;
      if (node.master_surface)
        return NodeClass::master;
      return node.slave_body ? NodeClass::inner_slave : NodeClass::inner_master;
    };
    std::vector<std::size_t> order(nodes.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      const int ca = static_cast<int>(class_of(nodes[a])), cb = static_cast<int>(class_of(nodes[b]));
      return ca != cb ? ca < cb : nodes[a].dofs[0] < nodes[b].dofs[0];
    });
    std::array<int, 5> local_counts{};
    for (const auto& node : nodes)
      ++local_counts[static_cast<int>(class_of(node))];
    std::vector<int> all_counts(5 * n_ranks);
    MPI_Allgather(local_counts.data(), 5, MPI_INT, all_counts.data(), 5, MPI_INT, comm);

    ContactLinearSystem result;
    std::array<GO, 5>   first_of_class{}; // first node id of this rank in class c
    GO                  offset = 0;
    for (int c = 0; c < 5; ++c)
      {
        long long total = 0;
        for (unsigned int r = 0; r < n_ranks; ++r)
          {
            if (r == rank)
              first_of_class[c] = offset + total;
            total += all_counts[5 * r + c];
          }
        result.class_sizes[c] = total;
        offset += total;
      }
    const GO n_primal = dim * offset;

    // New global id of every owned DOF, then of the ghosts through a ghosted vector.
    dealii::TrilinosWrappers::MPI::Vector new_id(owned, comm);
    std::vector<GO>                       primal_gids;
    std::vector<std::array<double, dim>>  coordinates;
    std::vector<GlobalIndex>              primal_assembly;
    std::array<GO, 5>                     next = first_of_class;
    std::map<int, LO>                     local_node_of_slave; // slave index -> local primal node
    for (std::size_t i : order)
      {
        const auto& node = nodes[i];
        const int   c    = static_cast<int>(class_of(node));
        const GO    id   = next[c]++;
        if (node.slave_index >= 0)
          local_node_of_slave[node.slave_index] = static_cast<LO>(primal_gids.size() / dim);
        for (int d = 0; d < dim; ++d)
          {
            new_id[node.dofs[d]] = static_cast<double>(dim * id + d);
            primal_gids.push_back(dim * id + d);
            primal_assembly.push_back(node.dofs[d]);
          }
        coordinates.push_back(node.position);
      }
    new_id.compress(dealii::VectorOperation::insert);

    // Multipliers: inactive then active, rank by rank, by first DOF within a rank. Each rank
    // numbers the slave nodes it owns (their multiplier rows live here); the new id of
    // multiplier (j, c) travels, like the displacements' new ids, in a vector of the
    // displacement layout, at node j's DOF c (the multiplier's assembly index minus n_dofs).
    std::vector<unsigned int> mine; // owned slave nodes (contact's list), by first DOF
    for (unsigned int j = 0; j < contact.n_slave_nodes(); ++j)
      if (contact.owns_slave_node(j))
        mine.push_back(j);
    std::sort(mine.begin(), mine.end(), [&](unsigned int a, unsigned int b) {
      return contact.slave_nodes()[a].dofs[0] < contact.slave_nodes()[b].dofs[0];
    });
    std::array<int, 2> mine_counts{};
    for (unsigned int j : mine)
      ++mine_counts[state.active[j] ? 1 : 0];
    std::vector<int> all_mine(2 * n_ranks);
    MPI_Allgather(mine_counts.data(), 2, MPI_INT, all_mine.data(), 2, MPI_INT, comm);
    std::array<GO, 2> next_lambda{};
    GO                n_lambda_nodes = 0;
    for (int active = 0; active < 2; ++active)
      for (unsigned int r = 0; r < n_ranks; ++r)
        {
          if (r == rank)
            next_lambda[active] = n_lambda_nodes;
          n_lambda_nodes += all_mine[2 * r + active];
        }
    dealii::TrilinosWrappers::MPI::Vector lambda_id(owned, comm);
    std::map<unsigned int, GO>            lambda_node; // owned slave node -> multiplier node id
    for (unsigned int j : mine)
      {
        const GO id    = next_lambda[state.active[j] ? 1 : 0]++;
        lambda_node[j] = id;
        for (int c = 0; c < dim; ++c)
          lambda_id[contact.slave_nodes()[j].dofs[c]] = static_cast<double>(dim * id + c);
      }
    lambda_id.compress(dealii::VectorOperation::insert);

    // Columns of the contact rows may name DOFs far from this rank (a master row gets the slave
    // side's columns): the ghosted copies cover them too. Collected first and added at once.
    std::vector<GlobalIndex> primal, multiplier;
    for (const auto& [row, entries] : rows)
      for (const auto& [col, value] : entries)
        (col >= n_dofs ? multiplier : primal).push_back(col >= n_dofs ? col - n_dofs : col);
    dealii::IndexSet primal_columns(ghosts), lambda_columns(n_dofs);
    add_unsorted_indices(primal_columns, std::move(primal));
    add_unsorted_indices(lambda_columns, std::move(multiplier));
    primal_columns.compress();
    lambda_columns.compress();
    dealii::TrilinosWrappers::MPI::Vector new_id_ghosted(owned, primal_columns, comm),
        lambda_id_ghosted(owned, lambda_columns, comm);
    new_id_ghosted    = new_id;
    lambda_id_ghosted = lambda_id;
    auto new_gid = [&](GlobalIndex assembly) -> GO {
      if (assembly >= n_dofs)
        return n_primal + static_cast<GO>(lambda_id_ghosted[assembly - n_dofs]);
      return static_cast<GO>(new_id_ghosted[assembly]);
    };
    std::vector<GO>          dual_gids;
    std::vector<GlobalIndex> dual_assembly;
    std::map<LO, LO>         dual_to_primal;
    std::sort(mine.begin(), mine.end(), [&](unsigned int a, unsigned int b) { return lambda_node[a] < lambda_node[b]; });
    for (unsigned int j : mine)
      {
        dual_to_primal[static_cast<LO>(dual_gids.size() / dim)] = local_node_of_slave.at(j);
        for (int c = 0; c < dim; ++c)
          {
            dual_gids.push_back(n_primal + dim * lambda_node[j] + c);
            dual_assembly.push_back(contact.multiplier_index(j, c));
          }
      }

    // The merged matrix, row by row in the final distribution.
    std::vector<GO> all_gids(primal_gids);
    all_gids.insert(all_gids.end(), dual_gids.begin(), dual_gids.end());
    result.assembly_index = primal_assembly;
    result.assembly_index.insert(result.assembly_index.end(), dual_assembly.begin(), dual_assembly.end());
    const GO    n_total = n_primal + dim * n_lambda_nodes;
    auto        row_map = Xpetra::MapFactory<LO, GO, NO>::Build(Xpetra::UseTpetra, n_total,
                                                                Teuchos::ArrayView<const GO>(all_gids), 0,
                                                                teuchos_comm(comm));
    auto b      = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(row_map, 1, true);
    auto b_data = b->getDataNonConst(0);
    std::vector<FlatRow> matrix_rows(all_gids.size());
    for (std::size_t i = 0; i < all_gids.size(); ++i)
      {
        const GlobalIndex    row = result.assembly_index[i];
        std::map<GO, double> entries;
        double               r = 0;
        if (row < n_dofs)
          {
            add_row(K, row, new_gid, entries);
            r = residual[row];
          }
        if (const auto it = rows.find(row); it != rows.end())
          for (const auto& [col, value] : it->second)
            entries[new_gid(col)] += value;
        if (const auto it = residual_pieces.find(row); it != residual_pieces.end())
          r += it->second;
        b_data[i] = -r;
        matrix_rows[i].assign(entries.begin(), entries.end());
      }
    auto A      = matrix_from_rows(comm, n_total, all_gids, matrix_rows);
    matrix_rows = {}; // gone before the blocks are extracted (held through from_merged, the peak)

    std::vector<BlockInfo> blocks(2);
    blocks[0].name          = "displacement";
    blocks[0].dofs_per_node = dim;
    blocks[0].global_size   = n_primal;
    blocks[1].name          = "lagrange multiplier";
    blocks[1].dofs_per_node = dim;
    blocks[1].global_size   = dim * n_lambda_nodes;
    result.system           = BlockSystem::from_merged(teuchos_comm(comm), blocks, {primal_gids, dual_gids}, A, b);

    std::vector<double> flat;
    for (const auto& x : coordinates)
      flat.insert(flat.end(), x.begin(), x.end());
    result.system.block(0).nullspace = rigid_body_modes(result.system.block(0).map, dim, flat);
    set_node_coordinates(result.system.block(0), dim, flat);

    // Interface data for the saddle-point AMG.
    InterfaceInfo   info;
    std::vector<GO> interface_dofs, slave_body, master_body;
    for (const auto& [dual, primal] : dual_to_primal)
      for (int d = 0; d < dim; ++d)
        interface_dofs.push_back(primal_gids[dim * primal + d]);
    const GO first_slave_gid = dim * (result.class_sizes[0] + result.class_sizes[1]);
    for (GO g : primal_gids)
      (g >= first_slave_gid ? slave_body : master_body).push_back(g);
    const auto invalid   = Teuchos::OrdinalTraits<Xpetra::global_size_t>::invalid();
    auto       build_map = [&](const std::vector<GO>& gids) {
      return Xpetra::MapFactory<LO, GO, NO>::Build(Xpetra::UseTpetra, invalid, Teuchos::ArrayView<const GO>(gids), 0,
                                                   teuchos_comm(comm));
    };
    info.dual_to_primal_node   = dual_to_primal;
    info.primal_interface_dofs = build_map(interface_dofs);
    info.slave_dofs            = build_map(slave_body);
    info.body_labels = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(result.system.block(0).map, 1);
    {
      // Rows of block 0 are the owned nodes in `order`, dim DOFs each.
      auto        labels = info.body_labels->getDataNonConst(0);
      std::size_t k      = 0;
      for (std::size_t i : order)
        for (int d = 0; d < dim; ++d)
          labels[k++] = nodes[i].body;
    }
    info.master_dofs           = build_map(master_body);
    result.system.set_interface(std::move(info));
    result.system.validate("contact Newton system");
    return result;
  }

  template ContactLinearSystem build_contact_system<2>(MPI_Comm, const std::vector<OwnedNode<2>>&,
                                                       const MortarContact<2>&, const dealii::IndexSet&,
                                                       const dealii::IndexSet&, const dealii::TrilinosWrappers::SparseMatrix&,
                                                       const dealii::TrilinosWrappers::MPI::Vector&, const RowPieces&,
                                                       const std::map<GlobalIndex, double>&);
  template ContactLinearSystem build_contact_system<3>(MPI_Comm, const std::vector<OwnedNode<3>>&,
                                                       const MortarContact<3>&, const dealii::IndexSet&,
                                                       const dealii::IndexSet&, const dealii::TrilinosWrappers::SparseMatrix&,
                                                       const dealii::TrilinosWrappers::MPI::Vector&, const RowPieces&,
                                                       const std::map<GlobalIndex, double>&);
} // namespace physics::contact
