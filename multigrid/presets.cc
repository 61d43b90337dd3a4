#include "presets.h"

#include <Teuchos_XMLParameterListHelpers.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace fs = std::filesystem;

namespace multigrid
{
  namespace
  {
    /// Preset names contain parentheses; their files use '_' instead: "sa-amg(cheapsimple)" is
    /// stored as "sa-amg_cheapsimple.xml".
    std::string file_name_of(const std::string& preset)
    {
      std::string f;
      for (char c : preset)
        if (c == '(')
          f += '_';
        else if (c != ')')
          f += c;
      return f + ".xml";
    }

    /// Teuchos reads a double or int parameter whose text is not a number as 0 without a word;
    /// every numeric value is checked here first, so that a typo is an error, not a zero.
    void check_numeric_values(const std::string& file)
    {
      std::ifstream     in(file);
      std::stringstream buffer;
      buffer << in.rdbuf();
      const std::string       text = buffer.str();
      static const std::regex parameter(
          R"re(<Parameter\s+name="([^"]*)"\s+type="(double|int)"\s+value="([^"]*)")re");
      for (auto it = std::sregex_iterator(text.begin(), text.end(), parameter); it != std::sregex_iterator();
           ++it)
        {
          const std::string name = (*it)[1], type = (*it)[2], value = (*it)[3];
          char*             end = nullptr;
          if (type == "double")
            std::strtod(value.c_str(), &end);
          else
            std::strtol(value.c_str(), &end, 10);
          if (value.empty() || *end != '\0')
            throw InputError(file + ": parameter '" + name + "' has value '" + value + "', expected a" +
                             (type == "int" ? "n integer" : " number"));
        }
    }

    Teuchos::ParameterList read_xml(const std::string& file)
    {
      if (!fs::is_regular_file(file))
        throw InputError(file + ": preset file not found");
      check_numeric_values(file);
      try
        {
          return *Teuchos::getParametersFromXmlFile(file);
        }
      catch (const std::exception& e)
        {
          std::string what = e.what();
          what.erase(std::remove(what.begin(), what.end(), '\n'), what.end());
          throw InputError(file + ": not a valid XML parameter list (" + what.substr(0, 200) + ")");
        }
    }

    Preset from_list(const std::string& name, const Teuchos::ParameterList& list, const std::string& file)
    {
      Preset p;
      p.name       = name;
      p.parameters = list;
      p.parameters.remove("name", false);
      p.kind = list.isParameter("kind") ? list.get<std::string>("kind") : std::string("muelu");
      static const std::vector<std::string> kinds = {"amg", "saddle-point-amg", "cheapsimple", "direct",
                                                     "muelu"};
      if (std::find(kinds.begin(), kinds.end(), p.kind) == kinds.end())
        throw InputError(file + ": parameter 'kind' is '" + p.kind +
                         "', expected amg, saddle-point-amg, cheapsimple, direct or muelu");
      return p;
    }
  } // namespace

  std::string preset_directory()
  {
    if (const char* env = std::getenv("SADDLE_POINT_PRESETS"); env && *env)
      {
        if (!fs::is_directory(env))
          throw InputError(std::string("SADDLE_POINT_PRESETS=") + env + ": not a directory");
        return env;
      }
    // The presets are data beside the executable, never the source tree: an installed app in
    // PREFIX/bin reads PREFIX/share/<project>/presets, one in the build tree (build/apps,
    // build/tests) the copy CMake keeps in build/share/<project>/presets. CMake sets both paths,
    // relative to the executable's directory.
    std::error_code ec;
    const fs::path  executable = fs::read_symlink("/proc/self/exe", ec);
    if (ec)
      throw InputError("solver presets: cannot locate the running executable (/proc/self/exe: " +
                       ec.message() + "); set SADDLE_POINT_PRESETS to the presets directory");
    std::vector<std::string> looked;
    for (const char* relative : {SADDLE_POINT_INSTALLED_PRESETS, SADDLE_POINT_BUILD_PRESETS})
      {
        const fs::path directory = (executable.parent_path() / relative).lexically_normal();
        if (fs::is_directory(directory))
          return directory.string();
        if (std::find(looked.begin(), looked.end(), directory.string()) == looked.end())
          looked.push_back(directory.string());
      }
    std::string where;
    for (const auto& d : looked)
      where += (where.empty() ? "" : " and ") + d;
    throw InputError("solver presets not found: looked in " + where + " (relative to " + executable.string() +
                     "); install the project or set SADDLE_POINT_PRESETS to the presets directory");
  }

  std::vector<std::string> available_presets()
  {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(preset_directory()))
      if (entry.path().extension() == ".xml")
        {
          const auto list = read_xml(entry.path().string());
          if (list.isParameter("name"))
            names.push_back(list.get<std::string>("name"));
        }
    std::sort(names.begin(), names.end());
    return names;
  }

  Preset load_preset(const std::string& name)
  {
    const std::string file = (fs::path(preset_directory()) / file_name_of(name)).string();
    if (!fs::is_regular_file(file))
      {
        std::string known;
        for (const auto& n : available_presets())
          known += (known.empty() ? "" : ", ") + n;
        throw InputError("--preset: unknown preset '" + name + "' (known: " + known + ")");
      }
    const auto        list   = read_xml(file);
    const std::string stored = list.isParameter("name") ? list.get<std::string>("name") : std::string();
    if (stored != name)
      throw InputError(file + ": parameter 'name' is '" + stored + "', expected '" + name + "'");
    return from_list(name, list, file);
  }

  Preset load_preset_file(const std::string& file)
  {
    const auto        list = read_xml(file);
    const std::string name =
        list.isParameter("name") ? list.get<std::string>("name") : fs::path(file).filename().string();
    return from_list(name, list, file);
  }

  void apply_overrides(Preset& preset, const std::vector<std::string>& overrides)
  {
    for (const auto& o : overrides)
      {
        const auto eq = o.find('=');
        if (eq == std::string::npos || eq == 0)
          throw InputError("--set '" + o + "': expected PATH=VALUE");
        const std::string       path = o.substr(0, eq), value = o.substr(eq + 1);
        Teuchos::ParameterList* list = &preset.parameters;
        std::string             rest = path;
        for (auto slash = rest.find('/'); slash != std::string::npos; slash = rest.find('/'))
          {
            const std::string sub = rest.substr(0, slash);
            if (!list->isSublist(sub))
              throw InputError("--set '" + o + "': preset '" + preset.name + "' has no sublist '" + sub +
                               "'");
            list = &list->sublist(sub);
            rest = rest.substr(slash + 1);
          }
        try
          {
            if (!list->isParameter(rest) || list->isType<std::string>(rest))
              list->set(rest, value);
            else if (list->isType<int>(rest))
              list->set(rest, std::stoi(value));
            else if (list->isType<double>(rest))
              list->set(rest, std::stod(value));
            else if (list->isType<bool>(rest))
              {
                if (value != "true" && value != "false")
                  throw std::invalid_argument("bool");
                list->set(rest, value == "true");
              }
            else
              throw InputError("--set '" + o + "': parameter '" + rest +
                               "' cannot be set from the command line");
          }
        catch (const std::invalid_argument&)
          {
            throw InputError("--set '" + o + "': value '" + value + "' does not fit the type of '" + rest +
                             "'");
          }
        catch (const std::out_of_range&)
          {
            throw InputError("--set '" + o + "': value '" + value + "' out of range");
          }
      }
  }

  std::string expand_template(const Preset& preset, int primal_dpn, int dual_dpn)
  {
    const auto&   p    = preset.parameters;
    const auto    file = (fs::path(preset_directory()) / p.get<std::string>("template")).string();
    std::ifstream in(file);
    if (!in)
      throw InputError(file + ": template of preset '" + preset.name + "' not found");
    std::stringstream buffer;
    buffer << in.rdbuf();
    std::string text = buffer.str();

    auto replace_all = [&text](const std::string& key, const std::string& value) {
      const std::string token = "@" + key + "@";
      for (auto pos = text.find(token); pos != std::string::npos; pos = text.find(token, pos + value.size()))
        text.replace(pos, token.size(), value);
    };
    replace_all("PRIMAL_DPN", std::to_string(primal_dpn));
    replace_all("DUAL_DPN", std::to_string(dual_dpn));
    const auto& values = p.sublist("template parameters");
    for (auto it = values.begin(); it != values.end(); ++it)
      replace_all(values.name(it), Teuchos::toString(values.entry(it).getAny()));

    // Strip the comment before searching for left-over placeholders (it mentions the syntax).
    const std::string body = std::regex_replace(text, std::regex("<!--[\\s\\S]*?-->"), "");
    std::smatch       m;
    if (std::regex_search(body, m, std::regex("@([A-Z_]+)@")))
      throw InputError("preset '" + preset.name + "': template parameter '" + m[1].str() +
                       "' has no value (add it to 'template parameters')");
    return text;
  }
} // namespace multigrid
