#include "muelu_xml_compat.h"

#include <set>

namespace multigrid
{
  namespace
  {
    const std::string newer_map_name = "PrimalInterfaceDofRowMap";
    const std::string map_name_13_2  = "Primal interface DOF map";

    void adapt(Teuchos::ParameterList& list, std::set<std::string>& changes)
    {
      std::vector<std::string> names;
      for (auto it = list.begin(); it != list.end(); ++it)
        names.push_back(list.name(it));
      for (const auto& name : names)
        {
          if (list.isSublist(name))
            {
              adapt(list.sublist(name), changes);
              continue;
            }
          if (list.isType<std::string>(name))
            {
              const auto value = list.get<std::string>(name);
              if (value == newer_map_name)
                {
                  list.set(name, map_name_13_2);
                  changes.insert("map name '" + newer_map_name + "' -> '" + map_name_13_2 + "'");
                }
              if (name == "nullspace vectors: limit to" &&
                  (value == "2D translations" || value == "3D translations"))
                {
                  list.set(name, std::string("all"));
                  changes.insert("'nullspace vectors: limit to' " + value + " -> all");
                }
            }
          if (name == newer_map_name)
            {
              list.setEntry(map_name_13_2, list.getEntry(name));
              list.remove(name);
              changes.insert("parameter '" + newer_map_name + "' -> '" + map_name_13_2 + "'");
            }
        }
    }
  } // namespace

  std::vector<std::string> adapt_muelu_xml_to_13_2(Teuchos::ParameterList& list)
  {
    std::set<std::string> changes;
    adapt(list, changes);
    std::vector<std::string> lines;
    for (const auto& c : changes)
      lines.push_back("MueLu XML adapted to MueLu 13.2: " + c);
    return lines;
  }
} // namespace multigrid
