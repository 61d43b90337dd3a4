// Named solver presets. Each preset is an XML parameter list under multigrid/presets/ whose
// "kind" says how it is built:
//   amg               single-field MueLu (sublist "MueLu": MueLu's parameter list, nullspace-aware)
//   saddle-point-amg  fully coupled block AMG: the MueLu XML template named by "template", its
//                     @PARAMETERS@ filled from the sublist "template parameters" and the system
//   cheapsimple       CheapSIMPLE(C) block preconditioner with inner solvers (sublists "primal
//                     solver", "schur solver": MueLu parameter lists)
//   direct            SuperLU on the whole system (the project's adaptor)
//   muelu             a complete MueLu XML of the user's (--xml FILE without a "kind")
//   fully-coupled-amg one monolithic SA-AMG for n x n blocks, block Gauss-Seidel level smoother
//                     (fully_coupled_amg.h)
//   block-relaxation  block Gauss-Seidel / Jacobi outside, one solver per block (block_relaxation.h)
// A preset file may name another shipped preset in "based on": it then holds only its changes,
// merged into that preset's parameters entry by entry (fully-coupled-pa-amg_bgs.xml).
// Any value can be overridden: "PATH=VALUE" with '/' between sublists, e.g.
// "template parameters/MAX_LEVELS=2" or "primal solver/max levels=2".
#pragma once

#include "types.h"

#include <Teuchos_ParameterList.hpp>

#include <string>
#include <vector>

namespace multigrid
{
  struct Preset
  {
    std::string            name;
    std::string            kind;
    Teuchos::ParameterList parameters;
  };

  /// Directory holding the preset XML files: $SADDLE_POINT_PRESETS if set, else found relative to
  /// the running executable (PREFIX/share/<project>/presets when installed, the build tree's copy
  /// build/share/<project>/presets otherwise). Throws InputError naming where it looked.
  std::string preset_directory();

  /// Names of all presets shipped in preset_directory(), in a stable order.
  std::vector<std::string> available_presets();

  /// Loads a shipped preset by name. Throws InputError naming the preset and the known ones.
  Preset load_preset(const std::string& name);

  /// Loads a user's XML file (a preset file, or a complete MueLu XML: kind "muelu").
  Preset load_preset_file(const std::string& file);

  /// Applies "PATH=VALUE" overrides; the value is converted to the type of the existing entry
  /// (a template parameter: checked against the type of the template's entry). A sublist or
  /// parameter the preset lacks is refused (InputError listing the known ones), except a parameter
  /// of MueLu's master list at the top of a MueLu list ("MueLu", "primal solver", "schur solver",
  /// "block solvers/NAME")
  /// and CheapSIMPLE's optional keys (predictor, schur nullspace, spai: ...) at the top level.
  /// An override written "[P1, P2] PATH=VALUE" applies only when the preset is one of those named
  /// (so a parameter file can carry the settings of several presets and the preset can be switched
  /// with one --set); a name in brackets that is no shipped preset is refused.
  void apply_overrides(Preset& preset, const std::vector<std::string>& overrides);

  /// The what() of a Trilinos exception (a preset's parameters refused by Teuchos or MueLu) as
  /// one clean line: the message without Teuchos' throw-site header (source path, throw number,
  /// failed test), line breaks as spaces, at most 400 characters.
  std::string one_line_message(const std::string& what);

  /// For saddle-point-amg presets: the MueLu XML text after substitution.
  std::string expand_template(const Preset& preset, int primal_dofs_per_node, int dual_dofs_per_node);
} // namespace multigrid
