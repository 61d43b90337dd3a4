// Shared pieces of the test programs.
#pragma once

#include <cctype>
#include <string>
#include <vector>

namespace test_helpers
{
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
