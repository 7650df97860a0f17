#include "vascsim/model/node_compliance.hpp"

#include <algorithm>

namespace vascsim {

bool NodeCompliance::prepare(const std::vector<Index>& nodes,
                             const EquilibriumPreconditioner& preconditioner) {
  if (preconditioner.version() != version_) {
    cache_.clear();
    version_ = preconditioner.version();
  }
  ++clock_;
  std::vector<Index> missing;
  for (Index i : nodes) {
    auto it = cache_.find(i);
    if (it != cache_.end())
      it->second.last_use = clock_;
    else if (std::find(missing.begin(), missing.end(), i) == missing.end())
      missing.push_back(i);
  }
  if (missing.empty()) return true;
  const auto m = static_cast<Eigen::Index>(missing.size());
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(free_.size(), 3 * m), Z;
  for (Eigen::Index c = 0; c < m; ++c)
    E.block<3, 3>(3 * static_cast<Eigen::Index>(
                          free_.slot[static_cast<std::size_t>(missing[static_cast<std::size_t>(c)])]),
                  3 * c) = Mat3::Identity();
  if (!preconditioner.solve_columns(E, Z)) return false;
  solved_ += 3 * m;
  // Room for the new nodes first, so none of the nodes asked for now is dropped.
  evict(capacity_ > missing.size() ? capacity_ - missing.size() : 0);
  for (Eigen::Index c = 0; c < m; ++c)
    cache_[missing[static_cast<std::size_t>(c)]] = {Z.middleCols<3>(3 * c), clock_};
  return true;
}

void NodeCompliance::evict(std::size_t keep_at_most) {
  while (cache_.size() > keep_at_most) {
    auto oldest = cache_.begin();
    for (auto it = cache_.begin(); it != cache_.end(); ++it)
      if (it->second.last_use < oldest->second.last_use) oldest = it;
    if (oldest->second.last_use == clock_) break;  // everything left is in use now
    cache_.erase(oldest);
  }
}

}  // namespace vascsim
