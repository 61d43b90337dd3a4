// Shared pieces of the test programs.
#pragma once

#include "types.h"

#include <Tpetra_Core.hpp>

#include <cctype>
#include <string>
#include <vector>

namespace test_helpers
{
  inline multigrid::RCP<const multigrid::Comm> comm()
  {
    return Tpetra::getDefaultComm();
  }

  /// A file of the peer systems (shared/peer-data, beside the repository).
  inline std::string peer(const std::string& name)
  {
    return std::string(PEER_DATA_DIR) + "/" + name;
  }

  /// The contact presets of the seeds' tables (and the direct reference).
  inline const std::vector<std::string> contact_presets = {
      "pa-amg(cheapsimple)",    "sa-amg(cheapsimple)", "emin(cheapsimple)",
      "sa-amg(braess-sarazin)", "sa-amg(uzawa)",       "fully-coupled-sa-amg(simple)",
      "cheapsimple(pa-amg)",    "cheapsimple(sa-amg)", "cheapsimplec(sgs)",
      "direct(superlu)"};

  /// GoogleTest parameter names must be identifiers: "sa-amg(uzawa)" -> "sa_amg_uzawa_".
  struct PresetName
  {
    template <typename Info>
    std::string operator()(const Info& info) const
    {
      std::string n;
      for (char c : info.param)
        n += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
      return n;
    }
  };
} // namespace test_helpers
