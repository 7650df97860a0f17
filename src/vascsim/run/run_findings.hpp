#pragma once
// What a finished run finds suspicious, gathered output point by output point (the records are not kept: a
// dynamic run may have 10^6): a tool that never touched the tissue, a tool whose contact the lattice did not
// resolve (contact_resolution.hpp), load steps that did not converge while a tool was in contact. `vascsim
// run` puts these lines in summary.json's warnings; the Python module issues them as warnings once the last
// output point is solved.

#include <cstddef>
#include <string>
#include <vector>

#include "vascsim/run/contact_resolution.hpp"
#include "vascsim/run/simulation.hpp"
#include "vascsim/scene/scene.hpp"

namespace vascsim {

class RunFindings {
 public:
  /// `scene` must outlive the findings.
  RunFindings(const Scene& scene, const Body& body);

  /// One output point's record, the initial one (step 0) included.
  void add(const StepRecord& r);

  /// One line each, in the order: unresolved contacts, tools that never touched the tissue (only once more
  /// than the initial record was added), load steps that did not converge in contact (with the load_steps
  /// value to try).
  std::vector<std::string> warnings(int load_steps) const;

 private:
  const Scene& scene_;
  std::vector<bool> touched_;
  std::vector<ContactResolution> resolution_;  // per tool
  int unconverged_in_contact_ = 0;
  std::size_t records_ = 0;
};

}  // namespace vascsim
