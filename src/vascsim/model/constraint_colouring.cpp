#include "vascsim/model/constraint_colouring.hpp"

#include <stdexcept>

namespace vascsim {

namespace {
// Node -> constraints containing it (CSR).
void invert(const std::vector<Index>& stencil_start, const std::vector<Index>& nodes, Index num_nodes,
            std::vector<Index>& node_start, std::vector<Index>& node_stencils) {
  node_start.assign(static_cast<std::size_t>(num_nodes) + 1, 0);
  for (Index n : nodes) {
    if (n < 0 || n >= num_nodes) throw std::invalid_argument("colour_stencils: node index out of range");
    ++node_start[static_cast<std::size_t>(n) + 1];
  }
  for (Index i = 0; i < num_nodes; ++i) node_start[i + 1] += node_start[i];
  node_stencils.resize(nodes.size());
  std::vector<Index> fill(node_start.begin(), node_start.end() - 1);
  const Index ns = static_cast<Index>(stencil_start.size()) - 1;
  for (Index s = 0; s < ns; ++s)
    for (Index e = stencil_start[s]; e < stencil_start[s + 1]; ++e) node_stencils[fill[nodes[e]]++] = s;
}
}  // namespace

Colouring colour_stencils(const std::vector<Index>& stencil_start, const std::vector<Index>& nodes,
                          Index num_nodes) {
  std::vector<Index> node_start, node_stencils;
  invert(stencil_start, nodes, num_nodes, node_start, node_stencils);
  const Index ns = stencil_start.empty() ? 0 : static_cast<Index>(stencil_start.size()) - 1;
  std::vector<int> colour(static_cast<std::size_t>(ns), -1);
  std::vector<Index> stamp;  // stamp[c] == s + 1: colour c is taken by a conflicting constraint of s
  int num_colours = 0;
  for (Index s = 0; s < ns; ++s) {
    for (Index e = stencil_start[s]; e < stencil_start[s + 1]; ++e) {
      const Index n = nodes[e];
      for (Index k = node_start[n]; k < node_start[n + 1]; ++k) {
        const int c = colour[node_stencils[k]];
        if (c >= 0) stamp[c] = s + 1;
      }
    }
    int c = 0;
    while (c < num_colours && stamp[c] == s + 1) ++c;
    if (c == num_colours) {
      ++num_colours;
      stamp.push_back(0);
    }
    colour[s] = c;
  }
  Colouring out;
  out.start.assign(static_cast<std::size_t>(num_colours) + 1, 0);
  for (int c : colour) ++out.start[c + 1];
  for (int c = 0; c < num_colours; ++c) out.start[c + 1] += out.start[c];
  out.order.resize(colour.size());
  std::vector<Index> pos(out.start.begin(), out.start.end() - 1);
  for (Index s = 0; s < ns; ++s) out.order[pos[colour[s]]++] = s;
  return out;
}

void node_stencils(const PairTable& pairs, std::vector<Index>& stencil_start, std::vector<Index>& nodes) {
  const Index n = static_cast<Index>(pairs.row_start.size()) - 1;
  stencil_start.assign(1, 0);
  nodes.clear();
  nodes.reserve(pairs.col.size() + static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i) {
    nodes.push_back(i);
    nodes.insert(nodes.end(), pairs.col.begin() + pairs.row_start[i],
                 pairs.col.begin() + pairs.row_start[i + 1]);
    stencil_start.push_back(static_cast<Index>(nodes.size()));
  }
}

bool is_valid_colouring(const Colouring& colouring, const std::vector<Index>& stencil_start,
                        const std::vector<Index>& nodes, Index num_nodes) {
  const Index ns = stencil_start.empty() ? 0 : static_cast<Index>(stencil_start.size()) - 1;
  if (static_cast<Index>(colouring.order.size()) != ns) return false;
  std::vector<char> seen(static_cast<std::size_t>(ns), 0);
  // Per node: the colour and the constraint that last touched it; a second constraint of the same colour
  // touching it is a conflict.
  std::vector<int> owner_colour(static_cast<std::size_t>(num_nodes), -1);
  std::vector<Index> owner(static_cast<std::size_t>(num_nodes), -1);
  for (int c = 0; c < colouring.num_colours(); ++c)
    for (Index k = colouring.start[c]; k < colouring.start[c + 1]; ++k) {
      const Index s = colouring.order[k];
      if (s < 0 || s >= ns || seen[s]) return false;
      seen[s] = 1;
      for (Index e = stencil_start[s]; e < stencil_start[s + 1]; ++e) {
        const Index n = nodes[e];
        if (owner_colour[n] == c && owner[n] != s) return false;
        owner_colour[n] = c;
        owner[n] = s;
      }
    }
  for (char v : seen)
    if (!v) return false;
  return true;
}

}  // namespace vascsim
