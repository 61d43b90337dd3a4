#include "presets.h"

#include "block_rebalancing.h"

#include <MueLu_MasterList.hpp>
#include <Teuchos_XMLParameterListHelpers.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <set>
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
          throw InputError(file + ": not a valid XML parameter list (" + one_line_message(e.what()) + ")");
        }
    }

    Teuchos::ParameterList read_preset_list(const std::string& file, std::set<std::string> chain = {});

    /// A preset may be written as its differences from another: "based on" names a shipped preset
    /// whose parameters it starts from; its own entries replace the base's or add to them, and a
    /// sublist is merged entry by entry (Teuchos' setParameters). So a variant states only what it
    /// changes (fully-coupled-pa-amg(bgs): the prolongator) and follows its base's other settings.
    Teuchos::ParameterList with_base(Teuchos::ParameterList list, const std::string& file,
                                     std::set<std::string> chain)
    {
      if (!list.isParameter("based on"))
        return list;
      if (!list.isType<std::string>("based on"))
        throw InputError(file + ": parameter 'based on' must be of type string");
      const std::string base = list.get<std::string>("based on");
      if (!chain.insert(base).second)
        throw InputError(file + ": parameter 'based on' is '" + base +
                         "', which is based on this preset (a cycle)");
      const std::string base_file = (fs::path(preset_directory()) / file_name_of(base)).string();
      if (!fs::is_regular_file(base_file))
        throw InputError(file + ": parameter 'based on' is '" + base + "', expected a shipped preset (no " +
                         base_file + ")");
      Teuchos::ParameterList merged = read_preset_list(base_file, chain);
      list.remove("based on");
      merged.setParameters(list);
      return merged;
    }

    /// The XML file's list with its base preset's entries merged in ("based on", recursively).
    Teuchos::ParameterList read_preset_list(const std::string& file, std::set<std::string> chain)
    {
      auto list = read_xml(file);
      if (list.isType<std::string>("name"))
        chain.insert(list.get<std::string>("name"));
      return with_base(std::move(list), file, std::move(chain));
    }

    /// What each kind's builder reads without a default, so that a preset file lacking one is
    /// refused when it is read (not as a Teuchos lookup error in the middle of the setup).
    void check_required_parameters(const Preset& p, const std::string& file)
    {
      struct Required
      {
        std::string kind, name, type; // type: "sublist", "string", "int", "double"
      };
      static const std::vector<Required> required = {{"amg", "MueLu", "sublist"},
                                                     {"saddle-point-amg", "template", "string"},
                                                     {"saddle-point-amg", "template parameters", "sublist"},
                                                     {"cheapsimple", "sweeps", "int"},
                                                     {"cheapsimple", "damping", "double"},
                                                     {"cheapsimple", "schur solver", "sublist"},
                                                     {"fully-coupled-amg", "max levels", "int"},
                                                     {"fully-coupled-amg", "coarse: max size", "int"},
                                                     {"fully-coupled-amg", "aggregation: min agg size", "int"},
                                                     {"fully-coupled-amg", "prolongator", "string"},
                                                     {"fully-coupled-amg", "sa: damping factor", "double"},
                                                     {"fully-coupled-amg", "smoother: sweeps", "int"},
                                                     {"fully-coupled-amg", "smoother: damping", "double"},
                                                     {"fully-coupled-amg", "smoother: max growth", "double"},
                                                     {"fully-coupled-amg", "block smoothers", "sublist"},
                                                     {"block-relaxation", "method", "string"},
                                                     {"block-relaxation", "sweeps", "int"},
                                                     {"block-relaxation", "damping", "double"},
                                                     {"block-relaxation", "block solvers", "sublist"}};
      const auto&                        l        = p.parameters;
      for (const auto& r : required)
        {
          const bool ok = r.type == "sublist"  ? l.isSublist(r.name)
                          : r.type == "string" ? l.isType<std::string>(r.name)
                          : r.type == "int"    ? l.isType<int>(r.name)
                                               : l.isType<double>(r.name);
          if (r.kind == p.kind && !ok)
            throw InputError(
                file + ": a preset of kind '" + p.kind + "' needs the " +
                (r.type == "sublist" ? "sublist '" + r.name + "'" : r.type + " parameter '" + r.name + "'"));
        }
    }

    Preset from_list(const std::string& name, const Teuchos::ParameterList& list, const std::string& file)
    {
      Preset p;
      p.name       = name;
      p.parameters = list;
      p.parameters.remove("name", false);
      if (list.isParameter("kind") && !list.isType<std::string>("kind"))
        throw InputError(file + ": parameter 'kind' must be of type string");
      p.kind = list.isParameter("kind") ? list.get<std::string>("kind") : std::string("muelu");
      static const std::vector<std::string> kinds = {"amg",    "saddle-point-amg", "cheapsimple",
                                                     "direct", "muelu", "fully-coupled-amg",
                                                     "block-relaxation"};
      if (std::find(kinds.begin(), kinds.end(), p.kind) == kinds.end())
        throw InputError(file + ": parameter 'kind' is '" + p.kind +
                         "', expected amg, saddle-point-amg, cheapsimple, direct, muelu, fully-coupled-amg or "
                         "block-relaxation");
      check_required_parameters(p, file);
      // Coarse-level rebalancing of the blocked hierarchies (block_rebalancing.h), off unless
      // asked for ("repartition/enable=true"); its defaults are written into the preset so that
      // overrides find them and --print-parameters shows them.
      if (p.kind == "saddle-point-amg" || p.kind == "fully-coupled-amg")
        {
          const RebalanceSettings defaults;
          auto&                   r = p.parameters.sublist("repartition");
          r.get("enable", defaults.enable);
          r.get("start level", defaults.start_level);
          r.get("min rows per proc", defaults.min_rows_per_proc);
          r.get("max imbalance", defaults.max_imbalance);
        }
      return p;
    }

    /// " (known: A, B, ...)" listing, sorted, the parameters (or the sublists) of `list`.
    std::string known_names(const Teuchos::ParameterList& list, bool sublists)
    {
      std::vector<std::string> names;
      for (auto it = list.begin(); it != list.end(); ++it)
        if (list.entry(it).isList() == sublists)
          names.push_back(list.name(it));
      std::sort(names.begin(), names.end());
      std::string known;
      for (const auto& n : names)
        known += (known.empty() ? "" : ", ") + n;
      return " (known: " + (known.empty() ? std::string("none") : known) + ")";
    }

    /// The lists of a preset that are MueLu parameter lists (MueLu reads and validates them).
    bool is_muelu_list(const Preset& preset, const std::string& parent)
    {
      const std::string block_solvers = "block solvers/"; // block-relaxation: one MueLu list per block
      return (preset.kind == "amg" && parent == "MueLu") ||
             (preset.kind == "cheapsimple" && (parent == "primal solver" || parent == "schur solver")) ||
             (preset.kind == "block-relaxation" && parent.rfind(block_solvers, 0) == 0 &&
              parent.find('/', block_solvers.size()) == std::string::npos);
    }

    /// Which parameters an override may add where a preset does not set them, with their types.
    /// Only two kinds of list read parameters they do not contain, with defaults:
    ///  - a MueLu parameter list (the "MueLu" list of an amg preset, the "primal solver" and
    ///    "schur solver" lists of a cheapsimple preset): any parameter of MueLu's master list,
    ///    typed as there (MueLu validates the list when it builds the hierarchy);
    ///  - the top level of a cheapsimple preset: the options CheapSIMPLE reads with a default.
    /// Everywhere else - "template parameters" (the placeholders of the template), the
    /// Ifpack2/Amesos2 sublists inside MueLu lists ("smoother: params", ...), a user's complete
    /// MueLu XML - a name the preset does not have is a typo, and refused.
    Teuchos::RCP<const Teuchos::ParameterList> addable_parameters(const Preset&      preset,
                                                                  const std::string& parent)
    {
      if (is_muelu_list(preset, parent))
        return MueLu::MasterList::List();
      auto optional = Teuchos::rcp(new Teuchos::ParameterList);
      if (preset.kind == "cheapsimple" && parent.empty())
        {
          optional->set("predictor", std::string("amg"));
          optional->set("update inverse approximation", std::string("diagonal"));
          optional->set("schur nullspace", std::string("none"));
          optional->set("spai: pattern power", 1);
          optional->set("spai: drop tolerance", 0.0);
        }
      return optional;
    }

    /// Adds `name` to `list` (the sublist `parent` of the preset) with the type it has where
    /// adding it is allowed, or throws listing the known parameters of that list.
    void add_new_parameter(const Preset& preset, Teuchos::ParameterList& list, const std::string& parent,
                           const std::string& name, const std::string& where)
    {
      const auto addable = addable_parameters(preset, parent);
      if (addable->isParameter(name) && !addable->isSublist(name))
        {
          // The type only: no validator, no "used" mark on MueLu's master list.
          list.setEntry(name, Teuchos::ParameterEntry(addable->getEntry(name).getAny(false)));
          return;
        }
      const std::string what = parent == "template parameters" ? "template parameter '"
                               : parent.empty()                ? "parameter '"
                                                               : "parameter in '" + parent + "' named '";
      throw InputError(where + ": preset '" + preset.name + "' has no " + what + name + "'" +
                       (is_muelu_list(preset, parent) ? ", nor has MueLu" : "") + known_names(list, false));
    }

    /// The type ("int", "double", "bool", "string") of a template parameter, from the XML entry
    /// of the template that receives it (value="@NAME@"); empty for anything else.
    std::string template_parameter_type(const Preset& preset, const std::string& parent,
                                        const std::string& name)
    {
      if (parent != "template parameters" || !preset.parameters.isType<std::string>("template") ||
          !std::regex_match(name, std::regex("[A-Za-z0-9_]+")))
        return "";
      std::ifstream     in(fs::path(preset_directory()) / preset.parameters.get<std::string>("template"));
      std::stringstream buffer;
      buffer << in.rdbuf();
      const std::string text = buffer.str();
      std::smatch       m;
      const std::regex  entry(R"re(type="(\w+)"\s+value="@)re" + name + "@\"");
      return std::regex_search(text, m, entry) ? m[1].str() : std::string();
    }

    /// `text` as a whole is an int (std::stoi would take "3x" as 3, "2.5" as 2).
    bool parses_as_int(const std::string& text, int& v)
    {
      char*      end = nullptr;
      const long l   = std::strtol(text.c_str(), &end, 10);
      if (text.empty() || *end != '\0' || l < std::numeric_limits<int>::min() ||
          l > std::numeric_limits<int>::max())
        return false;
      v = static_cast<int>(l);
      return true;
    }

    bool parses_as_double(const std::string& text, double& v)
    {
      char* end = nullptr;
      v         = std::strtod(text.c_str(), &end);
      return !text.empty() && *end == '\0' && std::isfinite(v);
    }

    /// Sets list[name] = value converted to the type of the existing entry (for a template
    /// parameter, a string checked against the type of the template's entry).
    void set_typed(Teuchos::ParameterList& list, const std::string& name, const std::string& value,
                   const std::string& where, const std::string& template_type)
    {
      int        i      = 0;
      double     d      = 0;
      const auto refuse = [&](const std::string& expected) {
        throw InputError(where + ": value '" + value + "' does not fit the type of '" + name +
                         "' (expected " + expected + ")");
      };
      const std::string type = !template_type.empty()           ? template_type
                               : list.isType<std::string>(name) ? "string"
                               : list.isType<int>(name)         ? "int"
                               : list.isType<double>(name)      ? "double"
                               : list.isType<bool>(name)        ? "bool"
                                                                : "";
      if (type == "int" && !parses_as_int(value, i))
        refuse("an integer");
      if (type == "double" && !parses_as_double(value, d))
        refuse("a number");
      if (type == "bool" && value != "true" && value != "false")
        refuse("true or false");
      if (type.empty())
        throw InputError(where + ": parameter '" + name +
                         "' is not a string, number or bool and cannot be overridden");
      if (!template_type.empty() || type == "string")
        list.set(name, value);
      else if (type == "int")
        list.set(name, i);
      else if (type == "double")
        list.set(name, d);
      else
        list.set(name, value == "true");
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
    const auto        list   = read_preset_list(file);
    const std::string stored = list.isParameter("name") ? list.get<std::string>("name") : std::string();
    if (stored != name)
      throw InputError(file + ": parameter 'name' is '" + stored + "', expected '" + name + "'");
    return from_list(name, list, file);
  }

  Preset load_preset_file(const std::string& file)
  {
    const auto        list = read_preset_list(file);
    const std::string name =
        list.isParameter("name") ? list.get<std::string>("name") : fs::path(file).filename().string();
    return from_list(name, list, file);
  }

  namespace
  {
    /// Splits "[P1, P2] PATH=VALUE" into the named presets and "PATH=VALUE" (no brackets: no
    /// names, the override applies to every preset). Every name must be a shipped preset, so a
    /// misspelt scope does not silently drop its override.
    std::vector<std::string> override_scope(const std::string& o, std::string& rest)
    {
      rest = o;
      if (o.empty() || o[0] != '[')
        return {};
      const auto close = o.find(']');
      if (close == std::string::npos)
        throw InputError("override '" + o + "': expected '[PRESET, ...] PATH=VALUE'");
      std::vector<std::string> names;
      std::stringstream        list(o.substr(1, close - 1));
      const auto               known = available_presets();
      for (std::string name; std::getline(list, name, ',');)
        {
          name.erase(0, name.find_first_not_of(' '));
          name.erase(name.find_last_not_of(' ') + 1);
          if (std::find(known.begin(), known.end(), name) == known.end())
            throw InputError("override '" + o + "': unknown preset '" + name + "' in its scope");
          names.push_back(name);
        }
      rest = o.substr(close + 1);
      rest.erase(0, rest.find_first_not_of(' '));
      return names;
    }
  } // namespace

  void apply_overrides(Preset& preset, const std::vector<std::string>& scoped_overrides)
  {
    for (const auto& item : scoped_overrides)
      {
        std::string o;
        const auto  scope = override_scope(item, o);
        if (!scope.empty() && std::find(scope.begin(), scope.end(), preset.name) == scope.end())
          continue; // written for other presets
        const auto eq = o.find('=');
        if (eq == std::string::npos || eq == 0)
          throw InputError("override '" + item + "': expected PATH=VALUE");
        const std::string where = "override '" + item + "'";
        const std::string path = o.substr(0, eq), value = o.substr(eq + 1);
        // Walk the sublists; none is created (a typo in a sublist name is an error).
        Teuchos::ParameterList* list = &preset.parameters;
        std::string             rest = path, parent;
        for (auto slash = rest.find('/'); slash != std::string::npos; slash = rest.find('/'))
          {
            const std::string sub = rest.substr(0, slash);
            if (!list->isSublist(sub))
              throw InputError(where + ": preset '" + preset.name + "' has no sublist '" + sub + "'" +
                               known_names(*list, true));
            parent = parent.empty() ? sub : parent + "/" + sub;
            list   = &list->sublist(sub);
            rest   = rest.substr(slash + 1);
          }
        if (list->isSublist(rest))
          throw InputError(where + ": '" + rest + "' is a sublist, not a parameter");
        if (!list->isParameter(rest))
          add_new_parameter(preset, *list, parent, rest, where);
        set_typed(*list, rest, value, where, template_parameter_type(preset, parent, rest));
      }
  }

  namespace
  {
    /// Every string-valued placeholder of a template names a factory (a sublist) of that
    /// template, e.g. value="Ainv-@SCHUR_INVERSE@": a value that names none (SCHUR_INVERSE=lumped)
    /// is refused here, with the values the template does define, instead of MueLu's factory
    /// lookup failing later without naming the template parameter.
    void check_factory_names(const Preset& preset, const std::string& text, const std::string& file)
    {
      const auto&           values = preset.parameters.sublist("template parameters");
      std::set<std::string> lists;
      const std::regex      list_name("<ParameterList name=\"([^\"]*)\"");
      for (std::sregex_iterator it(text.begin(), text.end(), list_name), end; it != end; ++it)
        lists.insert((*it)[1].str());
      const std::regex reference("type=\"string\" value=\"([^\"@]*)@([A-Z_]+)@([^\"@]*)\"");
      for (std::sregex_iterator it(text.begin(), text.end(), reference), end; it != end; ++it)
        {
          const std::string prefix = (*it)[1].str(), key = (*it)[2].str(), suffix = (*it)[3].str();
          if (!values.isParameter(key))
            continue; // reported as a placeholder without value
          const std::string value = Teuchos::toString(values.getEntry(key).getAny());
          if (lists.count(prefix + value + suffix))
            continue;
          std::string known;
          for (const auto& name : lists)
            if (name.size() > prefix.size() + suffix.size() && name.compare(0, prefix.size(), prefix) == 0 &&
                name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
              known += (known.empty() ? "" : ", ") +
                       name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
          throw InputError("preset '" + preset.name + "': template parameter " + key + " = '" + value +
                           "' names no factory of " + fs::path(file).filename().string() +
                           (prefix.empty() && suffix.empty() ? " (no sublist of that name)"
                                                             : " (expected one of: " + known + ")"));
        }
    }
  } // namespace

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
    check_factory_names(preset, text, file);
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

  std::string one_line_message(const std::string& what)
  {
    const auto collapsed = [](const std::string& text) { // whitespace runs as one space, trimmed
      std::string line;
      for (char c : text)
        if (!std::isspace(static_cast<unsigned char>(c)))
          line += c;
        else if (!line.empty() && line.back() != ' ')
          line += ' ';
      if (!line.empty() && line.back() == ' ')
        line.pop_back();
      return line;
    };
    // TEUCHOS_TEST_FOR_EXCEPTION writes "FILE:LINE:\n\nThrow number = N\n\nThrow test that
    // evaluated to true: TEST\n\nMESSAGE", its _PURE_MSG variant "MESSAGE\n\nThrow number = N",
    // a ParameterList lookup adds the list's contents; keep MESSAGE.
    std::string text = what;
    const auto  test = text.find("Throw test that evaluated to true:");
    if (test != std::string::npos && text.find("\n\n", test) != std::string::npos)
      text = text.substr(text.find("\n\n", test) + 2);
    for (const std::string tail : {"Throw number =", "The current parameters set in"})
      text = text.substr(0, text.find(tail));
    std::string line = collapsed(text);
    if (line.empty()) // nothing but Teuchos' header: better all of it than nothing
      line = collapsed(what);
    return line.size() > 400 ? line.substr(0, 400) + " ..." : line;
  }
} // namespace multigrid
