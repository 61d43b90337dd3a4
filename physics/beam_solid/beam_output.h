// VTK output of beams: every element drawn as a polyline through points of its Hermite
// centreline (current configuration), with the displacement and the coupling line load
// (interpolated linearly from the beam nodes) as point data. ParaView reads the .vtu directly.
#pragma once

#include "beam_solid/kirchhoff_beam.h"

#include <array>
#include <string>
#include <vector>

namespace physics::beam_solid
{
  /// Writes `file` atomically (a temporary file renamed into place). `dofs`: 6 per node
  /// (position and tangent displacements); `line_load`: one vector per node. Throws
  /// std::runtime_error naming the file if it cannot be written.
  void write_beam_vtu(const BeamMesh& beam, const std::vector<double>& dofs,
                      const std::vector<std::array<double, 3>>& line_load, const std::string& file,
                      int subdivisions = 4);
} // namespace physics::beam_solid
