#include "temporary_files.h"

#include <unistd.h>

#include <cstdio>
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
} // namespace multigrid
