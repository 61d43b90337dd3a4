// Names of the temporaries a process writes before renaming them into place. A fixed name such
// as FILE.tmp is shared by every process writing FILE: two runs at once would write into the same
// temporary and one would rename the other's half-written file. These names carry the process id
// and a random number, so no two processes (nor two calls) share one.
#pragma once

#include <string>

namespace multigrid
{
  /// "TARGET.<pid>-<random>.SUFFIX": beside `target` (the same directory, so that renaming it onto
  /// `target` is atomic) and used by no other process or call. Ends in ".SUFFIX", so a left-over
  /// temporary is still recognised by its suffix.
  std::string unique_temporary_name(const std::string& target, const std::string& suffix = "tmp");

  /// Writes `text` to a unique temporary beside `file` and renames it onto `file`: a reader never
  /// sees a half-written file. Throws InputError naming the file when it cannot.
  void write_file_atomically(const std::string& file, const std::string& text);
} // namespace multigrid
