#include "vascsim/model/wall_coarse_space.hpp"

#include <stdexcept>

namespace vascsim {

namespace {

// The coarse lines of one lattice direction and, for a fine line, the two coarse lines that bracket it.
struct CoarseLines {
  std::vector<int> index;  // per fine line: its coarse line number, -1 if not coarse
  int count = 0;
  int lines = 0;
  bool closed = false;  // columns close around the centre-line
  // The coarse lines before and after fine line f (equal when f itself is coarse).
  void bracket(int f, int& before, int& after) const {
    if (index[static_cast<std::size_t>(f)] >= 0) {
      before = after = f;
      return;
    }
    before = f - 1;  // even lines are coarse, so an odd line's neighbours are
    after = f + 1;
    if (closed && after == lines) after = 0;
  }
};

// Every second line from 0; the last line of an open direction too (its end), and of a closed one whose count
// is odd the last line is even anyway, so it closes onto line 0 one fine step away.
CoarseLines coarse_lines(int lines, bool closed) {
  CoarseLines c;
  c.lines = lines;
  c.closed = closed;
  c.index.assign(static_cast<std::size_t>(lines), -1);
  for (int f = 0; f < lines; ++f)
    if (f % 2 == 0 || (!closed && f == lines - 1)) c.index[static_cast<std::size_t>(f)] = c.count++;
  return c;
}

}  // namespace

bool has_wall_lattice(const Discretization& disc) {
  const auto& l = disc.cloud().wall_lattice;
  return l && l->columns >= 4 && l->sections >= 3 && l->layers >= 1 &&
         static_cast<Index>(l->layers) * l->columns * l->sections == disc.num_nodes();
}

NodalProlongation wall_coarse_space(const Discretization& disc, const std::vector<char>& constrained) {
  if (!has_wall_lattice(disc))
    throw std::invalid_argument("wall_coarse_space: the nodes form no wall lattice");
  const WallLatticeNumbering& L = *disc.cloud().wall_lattice;
  const Vec3Array& X = disc.rest_positions();
  const CoarseLines cols = coarse_lines(L.columns, true), secs = coarse_lines(L.sections, false);
  // Coarse node numbers: free lattice points on a coarse column and a coarse section.
  std::vector<Index> coarse_of(X.size(), -1);
  NodalProlongation P;
  for (int s = 0; s < L.sections; ++s)
    for (int c = 0; c < L.columns; ++c)
      for (int l = 0; l < L.layers; ++l) {
        const Index k = L.id(l, c, s);
        if (cols.index[static_cast<std::size_t>(c)] >= 0 && secs.index[static_cast<std::size_t>(s)] >= 0 &&
            !constrained[static_cast<std::size_t>(k)])
          coarse_of[static_cast<std::size_t>(k)] = P.coarse_nodes++;
      }
  // Per fine node: bilinear in (column, section) within its layer, each factor by rest distances.
  std::vector<std::vector<std::pair<Index, double>>> rows(X.size());
  auto share = [&](Index k, Index a, Index b) {  // the weight of b in the interpolation of k between a and b
    if (a == b) return 0.0;
    const double da = (X[static_cast<std::size_t>(k)] - X[static_cast<std::size_t>(a)]).norm();
    const double db = (X[static_cast<std::size_t>(k)] - X[static_cast<std::size_t>(b)]).norm();
    return da / (da + db);
  };
  for (int s = 0; s < L.sections; ++s)
    for (int c = 0; c < L.columns; ++c)
      for (int l = 0; l < L.layers; ++l) {
        const Index k = L.id(l, c, s);
        if (constrained[static_cast<std::size_t>(k)]) continue;
        int c0, c1, s0, s1;
        cols.bracket(c, c0, c1);
        secs.bracket(s, s0, s1);
        const double fc = share(k, L.id(l, c0, s), L.id(l, c1, s));
        const double fs = share(k, L.id(l, c, s0), L.id(l, c, s1));
        const int cs[2] = {c0, c1};
        const int ss[2] = {s0, s1};
        const double wc[2] = {1.0 - fc, fc};
        const double ws[2] = {1.0 - fs, fs};
        for (int a = 0; a < (c0 == c1 ? 1 : 2); ++a)
          for (int b = 0; b < (s0 == s1 ? 1 : 2); ++b) {
            const Index J = coarse_of[static_cast<std::size_t>(L.id(l, cs[a], ss[b]))];
            const double w = wc[a] * ws[b];
            if (J >= 0 && w > 0.0) rows[static_cast<std::size_t>(k)].push_back({J, w});
          }
      }
  P.row_start.assign(X.size() + 1, 0);
  for (std::size_t k = 0; k < X.size(); ++k) {
    P.row_start[k + 1] = P.row_start[k] + static_cast<std::int64_t>(rows[k].size());
    for (const auto& [J, w] : rows[k]) {
      P.coarse.push_back(J);
      P.weight.push_back(w);
    }
  }
  return P;
}

}  // namespace vascsim
