#include "common/run_directory.h"

#include "temporary_files.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace physics
{
  namespace fs = std::filesystem;

  void prepare_output_directory(const std::string& directory, MPI_Comm comm)
  {
    std::string error;
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      {
        std::error_code ec;
        fs::create_directories(directory, ec);
        if (ec)
          error = ec.message();
        else if (!fs::is_directory(directory))
          error = "not a directory";
        else
          {
            const std::string probe = multigrid::unique_temporary_name(directory + "/.write-test");
            if (!std::ofstream(probe))
              error = "not writable";
            fs::remove(probe, ec);
          }
      }
    error = dealii::Utilities::MPI::broadcast(comm, error, 0);
    if (!error.empty())
      throw std::invalid_argument("parameter 'Directory' (Output): cannot create '" + directory + "' (" + error + ")");
  }

  void write_used_parameters(const dealii::ParameterHandler& prm, const std::string& directory, MPI_Comm comm)
  {
    if (dealii::Utilities::MPI::this_mpi_process(comm) != 0)
      return;
    const std::string file = directory + "/used_parameters.prm", tmp = multigrid::unique_temporary_name(file);
    {
      std::ofstream out(tmp);
      prm.print_parameters(out, dealii::ParameterHandler::PRM);
      if (!out)
        throw std::runtime_error(file + ": cannot write the used parameters");
    }
    fs::rename(tmp, file);
  }

  void log_timer_summary(const dealii::TimerOutput& timer, JsonLinesLog& log, std::ostream& console, bool root,
                         MPI_Comm comm)
  {
    JsonLinesLog::Line line;
    line.add("event", std::string("timers"));
    std::ostringstream text;
    text << "Timers (wall seconds, largest rank):";
    bool first = true;
    for (const auto& [section, seconds] : timer.get_summary_data(dealii::TimerOutput::total_wall_time))
      {
        const double largest = dealii::Utilities::MPI::max(seconds, comm);
        std::string  key     = section;
        for (auto& c : key)
          if (c == ' ')
            c = '_';
        line.add(key + "_seconds", largest);
        text << (first ? " " : ", ") << section << " " << std::fixed << std::setprecision(2) << largest;
        first = false;
      }
    // Peak resident memory per rank (the figure of weak-scaling studies): the largest rank, which
    // rank that is (a rank far above the mean holds something the others do not), and the mean.
    dealii::Utilities::System::MemoryStats memory;
    dealii::Utilities::System::get_memory_stats(memory); // VmHWM: peak resident set, kB
    const auto peak = dealii::Utilities::MPI::min_max_avg(memory.VmHWM / 1024.0, comm);
    line.add("peak_memory_mb_max", peak.max)
        .add("peak_memory_mb_max_rank", static_cast<long long>(peak.max_index))
        .add("peak_memory_mb_mean", peak.avg);
    log.write(line);
    if (root)
      console << text.str() << "\nPeak memory per rank: max " << std::fixed << std::setprecision(1)
              << peak.max << " MB (rank " << peak.max_index << "), mean " << peak.avg << " MB\n";
  }
} // namespace physics
