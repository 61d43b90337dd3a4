#include "common/app_parameters.h"

#include "presets.h"
#include "types.h"

#include <Teuchos_ParameterListExceptions.hpp>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace fs = std::filesystem;

namespace physics
{
  namespace
  {
    const char* path_rules = R"(
Paths: a file named inside the parameter file (Mesh/Mesh file, Fibres/Beam file) is relative to
the parameter file's own directory; one given with --set, and every output directory
(Output/Directory, also when written in the file), is relative to the working directory.
Every entry of the file must be declared (--print-parameters lists them): a misspelt name, an
unknown subsection or a value outside its pattern is an error, exit status 2.
)";

    /// What the app declared: per section its entries (with their patterns) and subsections.
    /// ParameterHandler keeps its patterns private; its JSON print carries each pattern's
    /// description, from which deal.II rebuilds an equal pattern.
    struct Section
    {
      std::map<std::string, std::shared_ptr<const dealii::Patterns::PatternBase>> entries;
      std::map<std::string, Section>                                              sections;
    };

    using Path = std::vector<std::string>;

    /// The pattern of a description; a kind deal.II cannot rebuild (a custom pattern) is left
    /// to ParameterHandler::set to check.
    std::shared_ptr<const dealii::Patterns::PatternBase> pattern_from(const std::string& description)
    {
      std::unique_ptr<dealii::Patterns::PatternBase> pattern;
      try
        {
          pattern = dealii::Patterns::pattern_factory(description);
        }
      catch (const std::exception&)
        {
        }
      if (!pattern)
        pattern = std::make_unique<dealii::Patterns::Anything>();
      return pattern;
    }

    Section declared_section(const boost::property_tree::ptree& node)
    {
      Section s;
      for (const auto& [name, child] : node)
        {
          const auto description = child.get_child_optional("pattern_description");
          if (description && description->empty() && child.get_child_optional("value"))
            s.entries[name] = pattern_from(description->data());
          else
            s.sections[name] = declared_section(child);
        }
      return s;
    }

    Section declared(const dealii::ParameterHandler& prm)
    {
      std::stringstream json;
      prm.print_parameters(json, dealii::ParameterHandler::JSON);
      boost::property_tree::ptree tree;
      boost::property_tree::read_json(json, tree);
      return declared_section(tree);
    }

    /// "in section 'A/B'", or "at the top level".
    std::string section_name(const Path& path)
    {
      if (path.empty())
        return "at the top level";
      std::string name;
      for (const auto& p : path)
        name += (name.empty() ? "" : "/") + p;
      return "in section '" + name + "'";
    }

    /// Levenshtein distance, case-insensitive: the number of single-character edits.
    std::size_t edit_distance(const std::string& a, const std::string& b)
    {
      std::vector<std::size_t> row(b.size() + 1);
      for (std::size_t j = 0; j <= b.size(); ++j)
        row[j] = j;
      for (std::size_t i = 1; i <= a.size(); ++i)
        {
          std::size_t diagonal = row[0];
          row[0]               = i;
          for (std::size_t j = 1; j <= b.size(); ++j)
            {
              const bool        same = std::tolower(a[i - 1]) == std::tolower(b[j - 1]);
              const std::size_t next = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
              diagonal               = row[j];
              row[j]                 = next;
            }
        }
      return row[b.size()];
    }

    /// " (did you mean 'X'?)" for a near name (at most a third of the name's characters
    /// edited, or 2), else " (known: A, B, ...)".
    template <typename Map>
    std::string suggestion(const std::string& name, const Map& known)
    {
      if (known.empty())
        return " (there are none)";
      std::string best, all;
      std::size_t best_distance = std::string::npos;
      for (const auto& entry : known)
        {
          const std::size_t d = edit_distance(name, entry.first);
          if (d < best_distance)
            best_distance = d, best = entry.first;
          all += (all.empty() ? "" : ", ") + entry.first;
        }
      if (best_distance <= std::max<std::size_t>(2, name.size() / 3))
        return " (did you mean '" + best + "'?)";
      return " (known: " + all + ")";
    }

    /// The section of `entry` when it is declared elsewhere in the tree (a set outside its
    /// subsection), else empty.
    std::string section_declaring(const Section& s, const std::string& entry, const Path& path = {})
    {
      if (s.entries.count(entry) && !path.empty())
        return section_name(path).substr(3);
      for (const auto& [name, sub] : s.sections)
        {
          Path deeper = path;
          deeper.push_back(name);
          const std::string found = section_declaring(sub, entry, deeper);
          if (!found.empty())
            return found;
        }
      return "";
    }

    /// The pattern of `entry` in `section`; throws "unknown entry ..." naming the nearest one.
    const dealii::Patterns::PatternBase& pattern_of(const Section& root, const Section& section,
                                                    const Path& path, const std::string& entry,
                                                    const std::string& where)
    {
      const auto it = section.entries.find(entry);
      if (it != section.entries.end())
        return *it->second;
      const std::string elsewhere = section_declaring(root, entry);
      throw std::invalid_argument(where + ": unknown entry '" + entry + "' " + section_name(path) +
                                  (elsewhere.empty() ? suggestion(entry, section.entries)
                                                     : " (it is an entry of " + elsewhere + ")"));
    }

    const Section& subsection_of(const Section& section, const Path& path, const std::string& name,
                                 const std::string& where)
    {
      const auto it = section.sections.find(name);
      if (it == section.sections.end())
        throw std::invalid_argument(where + ": unknown section '" + name + "' " + section_name(path) +
                                    suggestion(name, section.sections));
      return it->second;
    }

    /// A pattern's description in words: deal.II's text form without the infinite bounds,
    /// e.g. "an integer n such that 1 <= n <= 1000", "any one of NeoHooke, SaintVenantKirchhoff".
    std::string in_words(const dealii::Patterns::PatternBase& pattern)
    {
      std::string text = pattern.description(dealii::Patterns::PatternBase::Text);
      for (const std::string infinite :
           {"-MAX_DOUBLE <= ", " <= MAX_DOUBLE", "-2147483648 <= ", " <= 2147483647"})
        for (auto pos = text.find(infinite); pos != std::string::npos; pos = text.find(infinite))
          text.erase(pos, infinite.size());
      for (const std::string bare : {" v such that v", " n such that n"})
        if (text.size() >= bare.size() && text.compare(text.size() - bare.size(), bare.size(), bare) == 0)
          text.erase(text.size() - bare.size());
      if (!text.empty())
        text[0] = static_cast<char>(std::tolower(text[0]));
      return text;
    }

    /// Sets `entry` of the section `path` to `value`, checked against the entry's pattern.
    void set_checked(dealii::ParameterHandler& prm, const dealii::Patterns::PatternBase& pattern,
                     const Path& path, const std::string& entry, const std::string& value,
                     const std::string& where)
    {
      if (!pattern.match(value))
        throw std::invalid_argument(where + ": value '" + value + "' of '" + entry + "' " +
                                    section_name(path) + " is not allowed, expected " + in_words(pattern));
      for (const auto& p : path)
        prm.enter_subsection(p);
      bool refused = false;
      try
        {
          prm.set(entry, value); // declared, and the pattern (unless a custom one) matched
        }
      catch (const dealii::ExceptionBase&)
        {
          refused = true;
        }
      for (std::size_t i = 0; i < path.size(); ++i)
        prm.leave_subsection();
      if (refused)
        throw std::invalid_argument(where + ": value '" + value + "' of '" + entry + "' " +
                                    section_name(path) + " is not allowed");
    }

    /// A file name written in the parameter file is relative to the file's directory.
    std::string resolved_input_path(const dealii::Patterns::PatternBase& pattern, const std::string& value,
                                    const fs::path& prm_directory)
    {
      const auto* file = dynamic_cast<const dealii::Patterns::FileName*>(&pattern);
      if (!file || file->file_type != dealii::Patterns::FileName::input || value.empty() ||
          fs::path(value).is_absolute())
        return value;
      return (prm_directory / value).lexically_normal().string();
    }

    std::string trimmed(const std::string& s)
    {
      const auto first = s.find_first_not_of(" \t\r");
      if (first == std::string::npos)
        return "";
      return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
    }

    /// `s` with control and non-ASCII bytes shown as '?' (a binary file given as parameter file).
    std::string printable(std::string s)
    {
      for (char& c : s)
        if (!std::isprint(static_cast<unsigned char>(c)))
          c = '?';
      return s;
    }

    bool starts_with_keyword(const std::string& line, const std::string& keyword)
    {
      if (line.size() <= keyword.size() || line[keyword.size()] != ' ')
        return false;
      std::string head = line.substr(0, keyword.size());
      std::transform(head.begin(), head.end(), head.begin(), [](unsigned char c) { return std::tolower(c); });
      return head == keyword;
    }

    /// An exception's message as one clean line: of a deal.II exception (also one quoted inside
    /// another message) its "Additional information" or violated condition, never the source
    /// line or stack trace; of a Teuchos one its message, not the throw site.
    std::string one_line(const std::string& what)
    {
      std::string text = what;
      for (const std::string head : {"Additional information:", "The violated condition was:"})
        if (text.find("An error occurred in line") != std::string::npos &&
            text.find(head) != std::string::npos)
          {
            text = text.substr(0, text.find("An error occurred in line")) +
                   text.substr(text.find(head) + head.size());
            break;
          }
      text = std::regex_replace(text.substr(0, text.find("Stacktrace:")), std::regex("-{4,}"), " ");
      return multigrid::one_line_message(text);
    }

    /// The lines of a prm file as deal.II reads them: a line ending in '\' continues on the next
    /// one, '#' starts a comment, tabs are spaces. Each with the number of its first line.
    std::vector<std::pair<int, std::string>> logical_lines(std::istream& in)
    {
      std::vector<std::pair<int, std::string>> lines;
      std::string                              raw, line;
      int                                      number = 0, first = 0;
      while (std::getline(in, raw))
        {
          ++number;
          raw = trimmed(raw);
          if (line.empty())
            first = number;
          const bool continued = !raw.empty() && raw.back() == '\\';
          line += continued ? raw.substr(0, raw.size() - 1) : raw;
          if (continued)
            continue;
          std::string text = trimmed(line.substr(0, line.find('#')));
          std::replace(text.begin(), text.end(), '\t', ' ');
          if (!text.empty())
            lines.emplace_back(first, text);
          line.clear();
        }
      return lines;
    }

    /// Reads a prm file into `prm`, every line checked against the declarations so that each
    /// error names its line: "subsection NAME", "end", "set NAME = VALUE".
    void read_parameter_file(const std::string& file, const Section& root, dealii::ParameterHandler& prm)
    {
      std::ifstream in(file);
      if (!in)
        throw std::invalid_argument(file + ": parameter file cannot be read");
      const fs::path                              directory = fs::path(file).parent_path();
      std::vector<std::pair<const Section*, int>> open      = {{&root, 0}}; // section, line opened
      Path                                        path;
      for (const auto& [number, text] : logical_lines(in))
        {
          const std::string where = file + ":" + std::to_string(number);
          const Section&    here  = *open.back().first;
          const auto        eq    = text.find('=');
          if (starts_with_keyword(text, "subsection"))
            {
              const std::string name = trimmed(text.substr(11));
              open.emplace_back(&subsection_of(here, path, name, where), number);
              path.push_back(name);
            }
          else if (text == "end" || text == "END")
            {
              if (path.empty())
                throw std::invalid_argument(where + ": 'end' without an open subsection");
              open.pop_back();
              path.pop_back();
            }
          else if (starts_with_keyword(text, "set") && eq != std::string::npos &&
                   !trimmed(text.substr(4, eq - 4)).empty())
            {
              const std::string entry   = trimmed(text.substr(4, eq - 4));
              const auto&       pattern = pattern_of(root, here, path, entry, where);
              set_checked(prm, pattern, path, entry,
                          resolved_input_path(pattern, trimmed(text.substr(eq + 1)), directory), where);
            }
          else
            throw std::invalid_argument(
                where + ": cannot read '" + printable(text.substr(0, 60)) +
                "' (expected 'subsection NAME', 'set NAME = VALUE', 'end' or a # comment)");
        }
      if (!path.empty())
        throw std::invalid_argument(file + ":" + std::to_string(open.back().second) + ": subsection '" +
                                    path.back() + "' is not closed by 'end'");
    }

    /// --set "Section/Subsection/Entry=value": the value as given (a path relative to the
    /// working directory), checked like a line of the file.
    void apply_set(const std::string& s, const Section& root, dealii::ParameterHandler& prm)
    {
      const auto        eq    = s.find('=');
      const auto        slash = eq == std::string::npos ? std::string::npos : s.rfind('/', eq);
      const std::string where = "--set '" + s + "'";
      if (slash == std::string::npos || slash == 0)
        throw std::invalid_argument(where + ": expected Section/Entry=value");
      Path           path;
      const Section* section = &root;
      std::string    rest    = s.substr(0, slash);
      for (std::size_t next = 0; next != std::string::npos;)
        {
          next                   = rest.find('/');
          const std::string name = rest.substr(0, next);
          section                = &subsection_of(*section, path, name, where);
          path.push_back(name);
          rest = next == std::string::npos ? "" : rest.substr(next + 1);
        }
      const std::string entry = s.substr(slash + 1, eq - slash - 1);
      set_checked(prm, pattern_of(root, *section, path, entry, where), path, entry, s.substr(eq + 1), where);
    }
  } // namespace

  bool read_command_line(int argc, char** argv, const std::string& usage, dealii::ParameterHandler& prm,
                         bool root)
  {
    std::string              file;
    std::vector<std::string> sets;
    for (int i = 1; i < argc; ++i)
      {
        const std::string a = argv[i];
        if (a == "--help" || a == "-h")
          {
            if (root)
              std::cout << usage << path_rules;
            return false;
          }
        if (a == "--print-parameters")
          {
            if (root)
              prm.print_parameters(std::cout, dealii::ParameterHandler::Text);
            return false;
          }
        if (a == "--set" && i + 1 >= argc)
          throw std::invalid_argument("--set: missing \"Section/Entry=value\"");
        if (a == "--restart" && i + 1 >= argc)
          throw std::invalid_argument("--restart: missing the checkpoint directory");
        if (a == "--set")
          sets.push_back(argv[++i]);
        else if (a == "--restart")
          sets.push_back(std::string("Restart/Resume from=") + argv[++i]);
        else if (!a.empty() && a[0] != '-' && file.empty())
          file = a;
        else
          throw std::invalid_argument("unknown argument '" + a + "' (see --help)");
      }
    const Section declarations = declared(prm);
    if (!file.empty())
      {
        if (!fs::is_regular_file(file))
          throw std::invalid_argument(file + ": parameter file not found");
        read_parameter_file(file, declarations, prm);
      }
    for (const auto& s : sets)
      apply_set(s, declarations, prm);
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
          std::cerr << app << ": " << one_line(e.what()) << "\n";
        return 2;
      }
    catch (const std::invalid_argument& e)
      {
        if (root)
          std::cerr << app << ": " << one_line(e.what()) << "\n";
        return 2;
      }
    catch (const Teuchos::Exceptions::InvalidParameter& e) // a preset parameter MueLu refuses
      {
        if (root)
          std::cerr << app << ": " << one_line(e.what()) << "\n";
        return 2;
      }
    catch (const std::exception& e)
      {
        if (root)
          std::cerr << app << ": error: " << one_line(e.what()) << "\n";
        return 3;
      }
  }
} // namespace physics
