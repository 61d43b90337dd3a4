#include "contact/contact_pairs.h"

#include <stdexcept>

namespace physics::contact
{
  ContactPairs::ContactPairs(const std::vector<std::pair<unsigned int, unsigned int>>& listed,
                             const std::set<unsigned int>&                              bodies)
      : automatic_(listed.empty())
      , n_bodies_(bodies.size())
  {
    if (bodies.size() < 2)
      throw std::invalid_argument("contact: the contact surfaces lie on " + std::to_string(bodies.size()) +
                                  " body; expected at least two bodies (material ids) with contact faces");
    if (automatic_)
      {
        // The lower body id is the slave: the highest body is master only, the lowest slave only.
        for (const unsigned int b : bodies)
          {
            if (b != *bodies.rbegin())
              slave_bodies_.insert(b);
            if (b != *bodies.begin())
              master_bodies_.insert(b);
          }
        return;
      }
    for (const auto& [s, m] : listed)
      {
        for (const unsigned int b : {s, m})
          if (!bodies.count(b))
            throw std::invalid_argument("parameter 'Pairs': body " + std::to_string(b) +
                                        " has no contact faces (no cell with that material id next to a "
                                        "contact surface id)");
        if (s == m)
          throw std::invalid_argument("parameter 'Pairs': body " + std::to_string(s) +
                                      " paired with itself; self-contact is not handled");
        listed_.insert({s, m});
        slave_bodies_.insert(s);
        master_bodies_.insert(m);
      }
  }

  std::string ContactPairs::describe() const
  {
    if (automatic_)
      return "automatic pairs: " + std::to_string(n_bodies_) +
             " bodies, every body against every other, the lower body id is the slave (" +
             std::to_string(n_bodies_ * (n_bodies_ - 1) / 2) + " pairs)";
    std::string text = std::to_string(listed_.size()) + " pairs (slave:master):";
    for (const auto& [s, m] : listed_)
      text += " " + std::to_string(s) + ":" + std::to_string(m);
    return text;
  }
} // namespace physics::contact
