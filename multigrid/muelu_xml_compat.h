// A complete MueLu XML (`--xml FILE` without a "kind") written for a newer MueLu, read by MueLu 13.2.
//
// MueLu's meshtying test files after 13.2 transfer the slave-side primal interface DOF map to the
// coarse levels (dof-based InterfaceAggregationFactory on 3 or more levels) under the name
// "PrimalInterfaceDofRowMap", limited to the translations ("2D translations"/"3D translations").
// MueLu 13.2 reads that map as "Primal interface DOF map", and its interpreter silently drops
// factory parameters it does not know, so the coarse level's InterfaceAggregationFactory finds no
// factory for the map and the setup fails ("No default factory ... 'Primal interface DOF map' ...
// during request for data "P" on level 2"). Its MapTransferFactory knows only "all" and
// "translations" (one column), while its InterfaceAggregationFactory walks the coarse map in steps
// of the coarse DOFs per node (the nullspace dimension), i.e. expects all of them: "all".
#pragma once

#include <Teuchos_ParameterList.hpp>

#include <string>
#include <vector>

namespace multigrid
{
  /// Rewrites `list` (recursively) into MueLu 13.2's names, as above; returns one line per kind of
  /// change made (empty if the list already was 13.2's).
  std::vector<std::string> adapt_muelu_xml_to_13_2(Teuchos::ParameterList& list);
} // namespace multigrid
