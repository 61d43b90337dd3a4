#include "temporary_files.h"

#include "types.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

namespace multigrid
{
  std::string unique_temporary_name(const std::string& target, const std::string& suffix)
  {
    // The pid tells processes on one machine apart; the random part tells apart processes with
    // the same pid (other machines, other containers writing to a shared folder) and calls.
    static thread_local std::mt19937_64 random{std::random_device{}()};
    char                                tag[48];
    std::snprintf(tag, sizeof tag, ".%ld-%016llx.", static_cast<long>(::getpid()),
                  static_cast<unsigned long long>(random()));
    return target + tag + suffix;
  }

  void write_file_atomically(const std::string& file, const std::string& text)
  {
    const std::string tmp = unique_temporary_name(file);
    {
      std::ofstream out(tmp);
      out << text;
      if (!out)
        throw InputError(file + ": cannot write the file");
    }
    std::error_code ec;
    std::filesystem::rename(tmp, file, ec);
    if (ec)
      throw InputError(file + ": cannot move the file into place (" + ec.message() + ")");
  }
} // namespace multigrid
