#include "vascsim/run/run_findings.hpp"

#include <fmt/format.h>
#include <algorithm>

#include "vascsim/model/registry.hpp"

namespace vascsim {

RunFindings::RunFindings(const Scene& scene, const Body& body)
    : scene_(scene), touched_(scene.obstacles.size(), false) {
  // Each tool against the lattice's spacing where it meets the wall (spacing_under_tool_m).
  for (const RigidObstacle& tool : scene.obstacles) resolution_.emplace_back(tool, scene.material, body);
}

void RunFindings::add(const StepRecord& r) {
  bool contact = false;
  for (std::size_t o = 0; o < r.obstacles.size() && o < touched_.size(); ++o) {
    contact = contact || r.obstacles[o].contacts > 0;
    touched_[o] = touched_[o] || r.obstacles[o].contacts > 0 || r.obstacles[o].force_vector_n.norm() > 0.0;
    resolution_[o].add(r.obstacles[o].displacement_m, r.obstacles[o].force_vector_n.norm());
  }
  unconverged_in_contact_ += !r.report.converged && contact ? 1 : 0;
  ++records_;
}

std::vector<std::string> RunFindings::warnings(int load_steps) const {
  std::vector<std::string> out;
  for (const ContactResolution& r : resolution_)
    if (auto w = r.warning()) out.push_back(*w);
  for (std::size_t o = 0; o < touched_.size(); ++o)
    if (!touched_[o] && records_ > 1)
      out.push_back(
          fmt::format("the tool '{}' never touched the tissue (no contact and zero force at all {} "
                      "output points): check obstacles.{} (m)",
                      scene_.obstacles[o].name, records_ - 1, o));
  if (unconverged_in_contact_ > 0 && !find_model(scene_.model).capabilities.dynamic)
    out.push_back(fmt::format(
        "{} of {} load steps did not converge with a tool in contact: the contact changes "
        "too much in one step; use more load steps ({}.load_steps, now {}; try {})",
        unconverged_in_contact_, load_steps, scene_.model, load_steps, std::max(2 * load_steps, 12)));
  return out;
}

}  // namespace vascsim
