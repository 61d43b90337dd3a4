#include "common/checkpoint.h"

#include "common/row_exchange.h"
#include "common/run_output.h"

#include <deal.II/base/mpi.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace physics
{
  namespace
  {
    const std::string magic = "physics-checkpoint-1";

    // The files are a flat sequence of records: a string is its length (8 bytes) and its bytes,
    // a number list its count and its doubles. Both ends run on the same machine type (a restart
    // continues a run on the ranks that wrote it), so the native byte order is the format.
    void put(std::ostream& out, std::uint64_t n) { out.write(reinterpret_cast<const char*>(&n), sizeof n); }
    void put(std::ostream& out, const std::string& s)
    {
      put(out, static_cast<std::uint64_t>(s.size()));
      out.write(s.data(), static_cast<std::streamsize>(s.size()));
    }
    void put(std::ostream& out, const std::vector<double>& v)
    {
      put(out, static_cast<std::uint64_t>(v.size()));
      out.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(double)));
    }

    /// Reads records and turns a short or corrupt file into one error naming it.
    class Reader
    {
    public:
      explicit Reader(const std::string& file)
          : file_(file)
          , in_(file, std::ios::binary)
      {
        if (!in_)
          fail("missing");
        in_.seekg(0, std::ios::end);
        size_ = static_cast<std::uint64_t>(in_.tellg());
        in_.seekg(0);
      }
      std::uint64_t count()
      {
        std::uint64_t n = 0;
        in_.read(reinterpret_cast<char*>(&n), sizeof n);
        if (!in_)
          fail("truncated");
        return n;
      }
      std::string string()
      {
        const std::uint64_t n = bounded(count());
        std::string         s(n, '\0');
        in_.read(s.data(), static_cast<std::streamsize>(n));
        if (!in_)
          fail("truncated");
        return s;
      }
      std::vector<double> numbers()
      {
        const std::uint64_t n = bounded(count() * sizeof(double)) / sizeof(double);
        std::vector<double> v(n);
        in_.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(n * sizeof(double)));
        if (!in_)
          fail("truncated");
        return v;
      }
      [[noreturn]] void fail(const std::string& why) const
      {
        throw std::invalid_argument("checkpoint file '" + file_ + "': " + why + " (not a complete checkpoint)");
      }

    private:
      std::uint64_t bounded(std::uint64_t bytes)
      {
        if (bytes > size_)
          fail("corrupt");
        return bytes;
      }
      std::string   file_;
      std::ifstream in_;
      std::uint64_t size_ = 0;
    };

    std::string rank_file(const std::string& directory, unsigned int rank)
    {
      return directory + "/rank_" + std::to_string(rank) + ".bin";
    }
  } // namespace

  const std::vector<double>& Checkpoint::find(const std::map<std::string, std::vector<double>>& map,
                                              const std::string& key, const char* what) const
  {
    const auto it = map.find(key);
    if (it == map.end())
      throw std::invalid_argument("--restart '" + source_ + "': the checkpoint has no " + what + " '" + key +
                                  "' (written by another version of the program?)");
    return it->second;
  }

  double Checkpoint::number(const std::string& key) const
  {
    const auto& v = find(numbers_, key, "number");
    if (v.size() != 1)
      throw std::invalid_argument("--restart '" + source_ + "': checkpoint entry '" + key + "' is not one number");
    return v[0];
  }

  const std::vector<double>& Checkpoint::numbers(const std::string& key) const
  {
    return find(numbers_, key, "number list");
  }

  const std::string& Checkpoint::text(const std::string& key) const
  {
    const auto it = texts_.find(key);
    if (it == texts_.end())
      throw std::invalid_argument("--restart '" + source_ + "': the checkpoint has no text '" + key + "'");
    return it->second;
  }

  const std::vector<double>& Checkpoint::local(const std::string& key) const
  {
    return find(local_, key, "array");
  }

  void Checkpoint::store(const std::string& key, const dealii::TrilinosWrappers::MPI::Vector& v)
  {
    const dealii::IndexSet owned = v.locally_owned_elements();
    std::vector<double>    values;
    values.reserve(owned.n_elements());
    for (const auto i : owned)
      values.push_back(v[i]);
    set_local(key, std::move(values));
    set_local(key + "#layout", {static_cast<double>(v.size()), static_cast<double>(owned.n_elements()),
                                owned.n_elements() ? static_cast<double>(owned.nth_index_in_set(0)) : -1.0});
  }

  void Checkpoint::restore(const std::string& key, dealii::TrilinosWrappers::MPI::Vector& v) const
  {
    const dealii::IndexSet owned  = v.locally_owned_elements();
    const auto&            layout = local(key + "#layout");
    const double first = owned.n_elements() ? static_cast<double>(owned.nth_index_in_set(0)) : -1.0;
    if (layout.size() != 3 || layout[0] != static_cast<double>(v.size()) ||
        layout[1] != static_cast<double>(owned.n_elements()) || layout[2] != first)
      throw std::invalid_argument("--restart '" + source_ + "': vector '" + key +
                                  "' was written on another mesh or partition (global size " +
                                  std::to_string(static_cast<long long>(layout.empty() ? -1 : layout[0])) +
                                  ", this run " + std::to_string(v.size()) + ")");
    const auto& values = local(key);
    std::size_t k      = 0;
    for (const auto i : owned)
      v[i] = values[k++];
    v.compress(dealii::VectorOperation::insert);
  }

  void Checkpoint::store(const std::string& key, const std::map<dealii::types::global_dof_index, double>& entries)
  {
    std::vector<double> rows, values;
    for (const auto& [row, value] : entries)
      {
        rows.push_back(static_cast<double>(row)); // exact below 2^53
        values.push_back(value);
      }
    set_local(key + "#rows", std::move(rows));
    set_local(key, std::move(values));
  }

  void Checkpoint::restore(const std::string& key, std::map<dealii::types::global_dof_index, double>& entries) const
  {
    const auto& rows   = local(key + "#rows");
    const auto& values = local(key);
    if (rows.size() != values.size())
      throw std::invalid_argument("--restart '" + source_ + "': entries '" + key + "' are corrupt");
    entries.clear();
    for (std::size_t k = 0; k < rows.size(); ++k)
      entries[static_cast<dealii::types::global_dof_index>(rows[k])] = values[k];
  }

  void Checkpoint::write(const std::string& directory, MPI_Comm comm) const
  {
    const unsigned int rank  = dealii::Utilities::MPI::this_mpi_process(comm);
    const unsigned int ranks = dealii::Utilities::MPI::n_mpi_processes(comm);
    const std::string  tmp   = directory + ".tmp";
    std::string        error;
    if (rank == 0)
      {
        std::error_code ec;
        fs::remove_all(tmp, ec);
        if (!fs::create_directories(tmp, ec) || ec)
          error = "cannot create the checkpoint directory '" + tmp + "' (" + ec.message() + ")";
      }
    throw_if_any_rank_failed(error, comm);

    auto write_file = [&](const std::string& file, const auto& body) {
      std::ofstream out(file, std::ios::binary | std::ios::trunc);
      put(out, magic);
      put(out, kind_);
      body(out);
      out.close();
      if (!out)
        error = "cannot write the checkpoint file '" + file + "'";
    };
    write_file(rank_file(tmp, rank), [&](std::ostream& out) {
      put(out, static_cast<std::uint64_t>(rank));
      put(out, static_cast<std::uint64_t>(local_.size()));
      for (const auto& [key, values] : local_)
        {
          put(out, key);
          put(out, values);
        }
    });
    throw_if_any_rank_failed(error, comm);
    // The shared file last: a directory with it is complete.
    if (rank == 0)
      write_file(tmp + "/checkpoint.bin", [&](std::ostream& out) {
        put(out, static_cast<std::uint64_t>(ranks));
        put(out, static_cast<std::uint64_t>(numbers_.size()));
        for (const auto& [key, values] : numbers_)
          {
            put(out, key);
            put(out, values);
          }
        put(out, static_cast<std::uint64_t>(texts_.size()));
        for (const auto& [key, text] : texts_)
          {
            put(out, key);
            put(out, text);
          }
      });
    if (rank == 0 && error.empty())
      {
        std::error_code ec;
        fs::remove_all(directory, ec);
        fs::rename(tmp, directory, ec);
        if (ec)
          error = "cannot rename '" + tmp + "' to '" + directory + "' (" + ec.message() + ")";
      }
    throw_if_any_rank_failed(error, comm);
  }

  Checkpoint Checkpoint::read(const std::string& directory, const std::string& expected_kind, MPI_Comm comm)
  {
    const unsigned int rank  = dealii::Utilities::MPI::this_mpi_process(comm);
    const unsigned int ranks = dealii::Utilities::MPI::n_mpi_processes(comm);
    Checkpoint         c(expected_kind);
    c.source_ = directory;
    auto header = [&](Reader& in) {
      if (in.string() != magic)
        in.fail("not a checkpoint of this program");
      const std::string kind = in.string();
      if (kind != expected_kind)
        throw std::invalid_argument("--restart '" + directory + "': a checkpoint of " + kind + ", but this run is " +
                                    expected_kind);
    };
    std::string error;
    try
      {
        Reader shared(directory + "/checkpoint.bin");
        header(shared);
        const std::uint64_t written_on = shared.count();
        if (written_on != ranks)
          throw std::invalid_argument("--restart '" + directory + "': written on " + std::to_string(written_on) +
                                      " MPI ranks, this run has " + std::to_string(ranks) +
                                      " (a restart continues on the same number of ranks)");
        for (std::uint64_t n = shared.count(), i = 0; i < n; ++i)
          {
            const std::string key = shared.string();
            c.numbers_[key]       = shared.numbers();
          }
        for (std::uint64_t n = shared.count(), i = 0; i < n; ++i)
          {
            const std::string key = shared.string();
            c.texts_[key]         = shared.string();
          }
        Reader own(rank_file(directory, rank));
        header(own);
        if (own.count() != rank)
          own.fail("written by another rank");
        for (std::uint64_t n = own.count(), i = 0; i < n; ++i)
          {
            const std::string key = own.string();
            c.local_[key]         = own.numbers();
          }
      }
    catch (const std::invalid_argument& e)
      {
        error = e.what();
      }
    // Every rank stops with the same (the lowest rank's) message.
    const std::string message = lowest_rank_message(error, comm);
    if (!message.empty())
      throw std::invalid_argument(message);
    return c;
  }

  std::string CheckpointSeries::write(const Checkpoint& checkpoint, int step, MPI_Comm comm) const
  {
    std::ostringstream name;
    name << "step_" << std::setw(6) << std::setfill('0') << step;
    const std::string directory = root_ + "/" + name.str();
    const bool        root      = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
    std::string       previous;
    if (root)
      {
        std::ifstream latest(root_ + "/latest");
        std::getline(latest, previous);
        std::error_code ec;
        fs::create_directories(root_, ec);
      }
    checkpoint.write(directory, comm);
    if (root)
      {
        // `latest` moves on only now that the new checkpoint is complete; then the old one goes.
        write_atomically(root_ + "/latest", [&](std::ostream& out) { out << name.str() << "\n"; });
        std::error_code ec;
        if (!previous.empty() && previous != name.str() && previous.find('/') == std::string::npos)
          fs::remove_all(root_ + "/" + previous, ec);
      }
    MPI_Barrier(comm);
    return directory;
  }

  std::string CheckpointSeries::resolve(const std::string& path)
  {
    std::ifstream latest(path + "/latest");
    std::string   name;
    if (latest && std::getline(latest, name) && !name.empty())
      return path + "/" + name;
    return path;
  }
} // namespace physics
