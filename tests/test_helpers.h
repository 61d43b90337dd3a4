// Shared pieces of the test programs.
#pragma once

#include "types.h"

#include <Tpetra_Core.hpp>

#include <cctype>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace test_helpers
{
  inline multigrid::RCP<const multigrid::Comm> comm()
  {
    return Tpetra::getDefaultComm();
  }

  /// The message of the InputError that f() throws ("" if it throws none).
  inline std::string error_of(const std::function<void()>& f)
  {
    try
      {
        f();
      }
    catch (const multigrid::InputError& e)
      {
        return e.what();
      }
    return "";
  }

  /// A file (or the prefix P of P_matrix.mm) of the peer systems in tests/data/peer. Throws when
  /// it is missing, so the test fails instead of reading nothing.
  inline std::string peer(const std::string& name)
  {
    const std::string path = std::string(PEER_DATA_DIR) + "/" + name;
    if (!std::filesystem::is_regular_file(path) && !std::filesystem::is_regular_file(path + "_matrix.mm"))
      throw std::runtime_error("peer data missing: no " + path + " (nor " + path + "_matrix.mm)");
    return path;
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
