// Matrix Market files are checked here before Tpetra's reader sees them, so that a bad header, an
// index out of range, a missing entry or a non-finite value is one InputError naming the file and
// the line.
#include "block_system_io.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace multigrid
{
  MatrixMarketHeader scan_matrix_market(const std::string& file, bool check_entries)
  {
    std::ifstream in(file);
    if (!in)
      throw InputError(file + ": cannot open Matrix Market file");
    MatrixMarketHeader h;
    std::string        line;
    long long          line_no = 0;
    if (!std::getline(in, line) || line.rfind("%%MatrixMarket", 0) != 0)
      throw InputError(file + ":1: missing '%%MatrixMarket' banner");
    ++line_no;
    {
      std::istringstream s(line);
      std::string        banner, object, format, symmetry;
      s >> banner >> object >> format >> h.field >> symmetry;
      if (object != "matrix" || (format != "coordinate" && format != "array"))
        throw InputError(file + ":1: expected 'matrix coordinate' or 'matrix array'");
      h.coordinate = (format == "coordinate");
      if (symmetry != "general")
        throw InputError(file + ":1: symmetry '" + symmetry + "', only 'general' is supported");
    }
    bool      have_size = false;
    long long count     = 0;
    while (std::getline(in, line))
      {
        ++line_no;
        if (line.empty() || line[0] == '%')
          continue;
        std::istringstream s(line);
        const std::string  where = file + ":" + std::to_string(line_no) + ": ";
        if (!have_size)
          {
            if (!(s >> h.rows >> h.cols) || (h.coordinate && !(s >> h.entries)))
              throw InputError(where + "expected the size line");
            if (!h.coordinate)
              h.entries = h.rows * h.cols;
            have_size = true;
            if (!check_entries)
              return h;
            continue;
          }
        ++count;
        if (count > h.entries)
          throw InputError(where + "more entries than the " + std::to_string(h.entries) + " announced");
        std::string value;
        if (h.coordinate)
          {
            long long i = 0, j = 0;
            if (!(s >> i >> j >> value))
              throw InputError(where + "expected 'row column value'");
            if (i < 1 || i > h.rows || j < 1 || j > h.cols)
              throw InputError(where + "index (" + std::to_string(i) + ", " + std::to_string(j) +
                               ") outside the " + std::to_string(h.rows) + " x " + std::to_string(h.cols) +
                               " matrix");
          }
        else if (!(s >> value))
          throw InputError(where + "expected a value");
        char*        end = nullptr;
        const double v   = std::strtod(value.c_str(), &end);
        if (end == value.c_str() || *end != '\0' || !std::isfinite(v))
          throw InputError(where + "value '" + value + "' is not a finite number");
      }
    if (!have_size)
      throw InputError(file + ": no size line");
    if (count != h.entries)
      throw InputError(file + ": " + std::to_string(count) + " entries, the header announces " +
                       std::to_string(h.entries));
    return h;
  }
} // namespace multigrid
