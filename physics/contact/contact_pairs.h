// Which bodies meet in multi-body mortar contact (mortar_contact.h): a list of (slave body, master
// body) pairs of material ids, or the automatic rule "every body with contact faces against every
// other, the lower body id is the slave" (kept as a rule: no list of all pairs is built).
#pragma once

#include <set>
#include <string>
#include <utility>
#include <vector>

namespace physics::contact
{
  class ContactPairs
  {
  public:
    /// `listed` empty: automatic. `bodies`: the bodies that have contact faces. Throws
    /// std::invalid_argument naming parameter 'Pairs' for a body without contact faces, a body
    /// paired with itself, or fewer than two bodies.
    ContactPairs(const std::vector<std::pair<unsigned int, unsigned int>>& listed, const std::set<unsigned int>& bodies);

    /// May slave faces of body s meet master faces of body m?
    bool paired(unsigned int s, unsigned int m) const { return automatic_ ? s < m : listed_.count({s, m}) > 0; }
    /// Bodies that are slave (master) in at least one pair.
    const std::set<unsigned int>& slave_bodies() const { return slave_bodies_; }
    const std::set<unsigned int>& master_bodies() const { return master_bodies_; }
    /// One line for the log: the rule and the number of pairs, or the listed pairs.
    std::string describe() const;

  private:
    bool                                            automatic_ = true;
    std::size_t                                     n_bodies_  = 0;
    std::set<std::pair<unsigned int, unsigned int>> listed_;
    std::set<unsigned int>                          slave_bodies_, master_bodies_;
  };
} // namespace physics::contact
