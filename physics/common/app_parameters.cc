#include "common/app_parameters.h"

#include "types.h"

#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <vector>

namespace physics
{
  bool read_command_line(int argc, char** argv, const std::string& usage, dealii::ParameterHandler& prm, bool root)
  {
    std::string              file;
    std::vector<std::string> sets;
    for (int i = 1; i < argc; ++i)
      {
        const std::string a = argv[i];
        if (a == "--help" || a == "-h")
          {
            if (root)
              std::cout << usage;
            return false;
          }
        if (a == "--print-parameters")
          {
            if (root)
              prm.print_parameters(std::cout, dealii::ParameterHandler::Text);
            return false;
          }
        if (a == "--set" && i + 1 < argc)
          sets.push_back(argv[++i]);
        else if (!a.empty() && a[0] != '-' && file.empty())
          file = a;
        else
          throw std::invalid_argument("unknown argument '" + a + "' (see --help)");
      }
    if (!file.empty())
      {
        if (!std::filesystem::is_regular_file(file))
          throw std::invalid_argument(file + ": parameter file not found");
        try
          {
            prm.parse_input(file, "", true, true);
          }
        catch (const dealii::ExceptionBase& e)
          {
            // deal.II's message spans several lines; keep its explanation, on one line.
            std::string what = e.what();
            const auto  pos  = what.find("Additional information:");
            what             = pos == std::string::npos ? "cannot parse" : what.substr(pos + 24);
            std::string line;
            for (char c : what)
              line += (c == '\n') ? ' ' : c;
            throw std::invalid_argument(file + ": " + line.substr(0, 300));
          }
      }
    for (const auto& s : sets)
      {
        const auto eq = s.find('='), slash = s.rfind('/', eq);
        if (eq == std::string::npos || slash == std::string::npos)
          throw std::invalid_argument("--set '" + s + "': expected Section/Entry=value");
        prm.enter_subsection(s.substr(0, slash));
        try
          {
            prm.set(s.substr(slash + 1, eq - slash - 1), s.substr(eq + 1));
          }
        catch (const dealii::ExceptionBase&)
          {
            prm.leave_subsection();
            throw std::invalid_argument("--set '" + s + "': unknown parameter or value out of its pattern");
          }
        prm.leave_subsection();
      }
    return true;
  }

  int run_app(const std::string& app, bool root, const std::function<int()>& body)
  {
    try
      {
        return body();
      }
    catch (const multigrid::InputError& e)
      {
        if (root)
          std::cerr << app << ": " << e.what() << "\n";
        return 2;
      }
    catch (const std::invalid_argument& e)
      {
        if (root)
          std::cerr << app << ": " << e.what() << "\n";
        return 2;
      }
    catch (const std::exception& e)
      {
        if (root)
          std::cerr << app << ": error: " << e.what() << "\n";
        return 3;
      }
  }
} // namespace physics
