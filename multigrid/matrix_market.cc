// Matrix Market files are checked here, so that a bad header, an index out of range, a missing
// entry or a non-finite value is one InputError naming the file and the line; and sparse matrices
// are read here too: the check and the read are one pass over the file (Tpetra's reader parsed
// every line through a std::istream, and the check before it did the same once more: 14 s of a
// 16 s solve of the 3D tube's 8.6 M-entry system).
#include "block_system_io.h"

#include <MueLu_Utilities.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Export.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string_view>
#include <tuple>

namespace multigrid
{
  namespace
  {
    /// The lines of a file, read in large chunks (a line never spans two calls of `each`).
    template <typename F>
    void for_each_line(const std::string& file, F&& each)
    {
      std::unique_ptr<std::FILE, int (*)(std::FILE*)> in(std::fopen(file.c_str(), "rb"), &std::fclose);
      if (!in)
        throw InputError(file + ": cannot open Matrix Market file");
      std::vector<char> buffer(std::size_t(1) << 24);
      std::size_t       kept = 0; // bytes of an unfinished line at the buffer's start
      for (;;)
        {
          if (kept == buffer.size())
            buffer.resize(2 * buffer.size()); // a line longer than the buffer
          const std::size_t got   = std::fread(buffer.data() + kept, 1, buffer.size() - kept, in.get());
          const std::size_t end   = kept + got;
          const bool        eof   = got == 0;
          std::size_t       begin = 0;
          for (std::size_t i = 0; i < end; ++i)
            if (buffer[i] == '\n')
              {
                if (!each(buffer.data() + begin, buffer.data() + i))
                  return;
                begin = i + 1;
              }
          if (eof)
            {
              if (begin < end)
                each(buffer.data() + begin, buffer.data() + end);
              return;
            }
          kept = end - begin;
          std::copy(buffer.begin() + begin, buffer.begin() + end, buffer.begin());
        }
    }

    /// Splits [p, end) at blanks: the next token, or an empty one at the end of the line.
    std::string_view next_token(const char*& p, const char* end)
    {
      while (p < end && (*p == ' ' || *p == '\t' || *p == '\r'))
        ++p;
      const char* start = p;
      while (p < end && *p != ' ' && *p != '\t' && *p != '\r')
        ++p;
      return {start, static_cast<std::size_t>(p - start)};
    }

    template <typename T>
    bool parse(std::string_view token, T& value)
    {
      if (!token.empty() && token.front() == '+')
        token.remove_prefix(1);
      const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
      return error == std::errc() && end == token.data() + token.size() && !token.empty();
    }

    /// The header check and the pass over every entry line (with `check_entries`); `size` is
    /// called with the header once its size line is read, `entry` with the 1-based row and column
    /// (arrays: of the entry's place in column-major order) and the value of every entry.
    template <typename S, typename F>
    MatrixMarketHeader scan(const std::string& file, bool check_entries, S&& size, F&& entry)
    {
      MatrixMarketHeader h;
      long long          line_no = 0, count = 0;
      bool               have_size = false, done = false;
      for_each_line(file, [&](const char* p, const char* end) {
        ++line_no;
        if (line_no == 1)
          {
            const std::string line(p, end);
            if (line.rfind("%%MatrixMarket", 0) != 0)
              throw InputError(file + ":1: missing '%%MatrixMarket' banner");
            std::istringstream s(line);
            std::string        banner, object, format, symmetry;
            s >> banner >> object >> format >> h.field >> symmetry;
            if (object != "matrix" || (format != "coordinate" && format != "array"))
              throw InputError(file + ":1: expected 'matrix coordinate' or 'matrix array'");
            h.coordinate = (format == "coordinate");
            if (symmetry != "general")
              throw InputError(file + ":1: symmetry '" + symmetry + "', only 'general' is supported");
            return true;
          }
        const char* q = p;
        if (next_token(q, end).empty() || *p == '%')
          return true;
        const auto where = [&] { return file + ":" + std::to_string(line_no) + ": "; };
        if (!have_size)
          {
            if (!parse(next_token(p, end), h.rows) || !parse(next_token(p, end), h.cols) ||
                (h.coordinate && !parse(next_token(p, end), h.entries)))
              throw InputError(where() + "expected the size line");
            if (!h.coordinate)
              h.entries = h.rows * h.cols;
            have_size = true;
            size(h);
            done = !check_entries;
            return check_entries;
          }
        ++count;
        if (count > h.entries)
          throw InputError(where() + "more entries than the " + std::to_string(h.entries) + " announced");
        long long i = 1 + (count - 1) % std::max(h.rows, 1LL), j = 1 + (count - 1) / std::max(h.rows, 1LL);
        if (h.coordinate)
          {
            const auto ti = next_token(p, end), tj = next_token(p, end);
            if (!parse(ti, i) || !parse(tj, j))
              throw InputError(where() + "expected 'row column value'");
            if (i < 1 || i > h.rows || j < 1 || j > h.cols)
              throw InputError(where() + "index (" + std::to_string(i) + ", " + std::to_string(j) +
                               ") outside the " + std::to_string(h.rows) + " x " + std::to_string(h.cols) +
                               " matrix");
          }
        const auto token = next_token(p, end);
        if (token.empty())
          throw InputError(where() + (h.coordinate ? "expected 'row column value'" : "expected a value"));
        double v = 0.0;
        if (!parse(token, v) || !std::isfinite(v))
          throw InputError(where() + "value '" + std::string(token) + "' is not a finite number");
        entry(i, j, v);
        return true;
      });
      if (line_no == 0)
        throw InputError(file + ":1: missing '%%MatrixMarket' banner");
      if (!have_size)
        throw InputError(file + ": no size line");
      if (!done && count != h.entries)
        throw InputError(file + ": " + std::to_string(count) + " entries, the header announces " +
                         std::to_string(h.entries));
      return h;
    }

    /// A coordinate file's entries on rank 0 in compressed rows (0-based), duplicates summed,
    /// every row's columns sorted.
    struct RootRows
    {
      std::vector<std::size_t> offsets{0};
      std::vector<GO>          columns;
      std::vector<SC>          values;
    };

    RootRows read_rows(const std::string& file)
    {
      std::vector<std::tuple<GO, GO, SC>> entries;
      // Room for the announced entries, at most one per 6 bytes of the file ("1 1 0\n"), so that
      // a wrong header cannot ask for more memory than the file can fill.
      const auto reserve = [&](const MatrixMarketHeader& header) {
        const auto most = static_cast<long long>(std::filesystem::file_size(file) / 6);
        entries.reserve(static_cast<std::size_t>(std::clamp<long long>(header.entries, 0, most)));
      };
      const auto keep = [&](long long i, long long j, double v) { entries.emplace_back(i - 1, j - 1, v); };
      const auto h    = scan(file, true, reserve, keep);
      if (!h.coordinate)
        throw InputError(file + ": expected a Matrix Market coordinate matrix");
      // stable: duplicates are summed in the file's order
      std::stable_sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
        return std::tie(std::get<0>(a), std::get<1>(a)) < std::tie(std::get<0>(b), std::get<1>(b));
      });
      RootRows r;
      r.columns.reserve(entries.size());
      r.values.reserve(entries.size());
      std::size_t k = 0;
      for (GO row = 0; row < h.rows; ++row)
        {
          for (; k < entries.size() && std::get<0>(entries[k]) == row; ++k)
            if (r.columns.size() > r.offsets.back() && r.columns.back() == std::get<1>(entries[k]))
              r.values.back() += std::get<2>(entries[k]);
            else
              {
                r.columns.push_back(std::get<1>(entries[k]));
                r.values.push_back(std::get<2>(entries[k]));
              }
          r.offsets.push_back(r.columns.size());
        }
      return r;
    }
  } // namespace

  void on_root(const Comm& comm, const std::function<void()>& f)
  {
    std::string message;
    if (comm.getRank() == 0)
      {
        try
          {
            f();
          }
        catch (const InputError& e)
          {
            message = e.what();
          }
      }
    int length = static_cast<int>(message.size());
    Teuchos::broadcast(comm, 0, Teuchos::outArg(length));
    message.resize(length);
    if (length > 0)
      {
        Teuchos::broadcast(comm, 0, length, message.data());
        throw InputError(message);
      }
  }

  MatrixMarketHeader scan_matrix_market(const std::string& file, bool check_entries)
  {
    return scan(
        file, check_entries, [](const MatrixMarketHeader&) {}, [](long long, long long, double) {});
  }

  RCP<Matrix> read_sparse_matrix_market(const std::string& file, const RCP<const Map>& row_map)
  {
    using TpetraCrs = Tpetra::CrsMatrix<SC, LO, GO, NO>;
    using TpetraMap = Tpetra::Map<LO, GO, NO>;
    const auto map  = Xpetra::toTpetra(row_map);
    const auto comm = map->getComm();
    const bool root = comm->getRank() == 0;

    // Rank 0 reads and checks the whole file (an error reaches every rank as one InputError).
    RootRows rows;
    on_root(*comm, [&] { rows = read_rows(file); });
    GO n = static_cast<GO>(rows.offsets.size()) - 1;
    Teuchos::broadcast(*comm, 0, Teuchos::outArg(n));
    if (static_cast<Tpetra::global_size_t>(n) != map->getGlobalNumElements())
      throw InputError(file + ": " + std::to_string(n) + " rows, expected " +
                       std::to_string(map->getGlobalNumElements()));

    // The whole matrix on rank 0, then each row to its owner in `row_map`: fillComplete numbers
    // the columns as Tpetra's reader's matrix does (the same column map, the same entry order).
    const GO                 base      = map->getIndexBase();
    auto                     whole_map = Teuchos::rcp(new TpetraMap(n, root ? n : 0, base, comm));
    std::vector<std::size_t> counts(root ? n : 0);
    for (std::size_t i = 0; i < counts.size(); ++i)
      counts[i] = rows.offsets[i + 1] - rows.offsets[i];
    auto whole = Teuchos::rcp(new TpetraCrs(whole_map, Teuchos::ArrayView<const std::size_t>(counts)));
    for (std::size_t i = 0; i < counts.size(); ++i)
      {
        const auto start = rows.offsets[i];
        for (auto k = start; k < rows.offsets[i + 1]; ++k)
          rows.columns[k] += base;
        whole->insertGlobalValues(static_cast<GO>(i) + base,
                                  Teuchos::ArrayView<const GO>(rows.columns.data() + start, counts[i]),
                                  Teuchos::ArrayView<const SC>(rows.values.data() + start, counts[i]));
      }
    rows = RootRows();
    whole->fillComplete(map, whole_map);
    Tpetra::Export<LO, GO, NO> exporter(whole_map, map);
    auto A = Tpetra::exportAndFillCompleteCrsMatrix<TpetraCrs>(whole, exporter, map, map);
    return MueLu::TpetraCrs_To_XpetraMatrix(A);
  }
} // namespace multigrid
