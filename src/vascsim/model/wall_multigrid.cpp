#include "vascsim/model/wall_multigrid.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <algorithm>
#include <atomic>
#include <stdexcept>

#include "vascsim/core/error.hpp"
#include "vascsim/core/sparse_cholesky.hpp"
#include "vascsim/core/stopwatch.hpp"
#include "vascsim/model/energy_tangents.hpp"
#include "vascsim/model/stabilizer_matrix.hpp"
#include "vascsim/model/wall_coarse_space.hpp"

namespace vascsim {

namespace {
long long next_version() {
  static std::atomic<long long> versions{1LL
                                         << 40};  // apart from the factors' versions (meshless_factor.cpp)
  return ++versions;
}
}  // namespace

WallMultigrid::Level::Level() : coarse(SparseCholeskyOptions{CholeskyOrdering::Default, true, true}) {}

bool WallMultigrid::supports(const Problem& problem) {
  return has_wall_lattice(problem.discretization()) && problem.discretization().energy_points() == 1;
}

WallMultigrid::WallMultigrid(const Problem& problem, const FreeDofs& free, const ContactActiveSet& contacts,
                             const WallMultigridOptions& options)
    : problem_(problem),
      free_(free),
      contacts_(contacts),
      options_(options),
      projection_(positive_projection(problem.energy())),
      window_factor_(options.single_precision_window) {
  if (!supports(problem))
    throw std::invalid_argument(
        "WallMultigrid: the nodes form no wall lattice with one energy point per node");
  const Discretization& disc = problem.discretization();
  const Index n = disc.num_nodes();
  shift_.assign(static_cast<std::size_t>(n), 0.0);
  for (Index i = 0; i < n; ++i)
    shift_[static_cast<std::size_t>(i)] = disc.masses()[static_cast<std::size_t>(i)] * options.inv_h2;
  // The stabiliser's Hessian is constant: its diagonal for the Jacobi blocks, its entries in the window.
  stab_diag_.assign(static_cast<std::size_t>(n), 0.0);
  const PointPrimitiveEnergy& energy = problem.energy();
  if (energy.stabilizer_matrix())
    stab_rows_ = energy.stabilizer_matrix()->matrix();
  else if (energy.options().stabilizer_alpha > 0.0)
    stab_rows_ = StabilizerMatrix(disc, energy.stabilizer_coefficients(),
                                  energy.options().stabilizer_fit == StabilizerFit::Quadratic)
                     .matrix();
  if (stab_rows_.rows() > 0)
    for (Index i = 0; i < n; ++i) stab_diag_[static_cast<std::size_t>(i)] = stab_rows_.coeff(i, i);
  // Node k's through-wall line is k / layers (the lattice numbers the layers fastest).
  layers_ = disc.cloud().wall_lattice->layers;
  line_start_.assign(1, 0);
  line_offset_.assign(1, 0);
  line_slot_.assign(static_cast<std::size_t>(n), -1);
  for (Index first = 0; first < n; first += layers_) {
    for (Index k = first; k < first + layers_; ++k)
      if (!problem.constrained()[static_cast<std::size_t>(k)]) {
        line_slot_[static_cast<std::size_t>(k)] = static_cast<Index>(line_nodes_.size()) - line_start_.back();
        line_nodes_.push_back(k);
      }
    const Index m = static_cast<Index>(line_nodes_.size()) - line_start_.back();
    line_start_.push_back(static_cast<Index>(line_nodes_.size()));
    line_offset_.push_back(line_offset_.back() + static_cast<std::size_t>(9 * m * m));
  }
  prolongation_ = wall_coarse_space(disc, problem.constrained());
  galerkin_ = std::make_unique<GalerkinHessian>(energy, prolongation_, shift_);
  const double along = std::max(1.0, disc.wall_stretch()) * disc.mean_spacing();
  window_m_ = options.window_spacings * along;
  window_slot_.assign(static_cast<std::size_t>(n), -1);
}

WallMultigrid::~WallMultigrid() = default;

double WallMultigrid::last_level_seconds() const {
  return level_ ? level_->build_s : 0.0;
}

std::unique_ptr<WallMultigrid::Level> WallMultigrid::build_level(const Vec3Array& x,
                                                                 std::unique_ptr<Level> reuse) const {
  const Stopwatch clock;
  auto level = reuse ? std::move(reuse) : std::make_unique<Level>();
  const Discretization& disc = problem_.discretization();
  energy_tangents(problem_.energy(), x, projection_, level->tangents);
  // The lines' blocks: energy i couples every two members of its stencil (itself and its neighbours) by
  // tangent_block(C_i, d_a, d_b); a line's block gathers the couplings of its own nodes.
  const PairTable& P = disc.pairs();
  const std::size_t lines = line_start_.size() - 1;
  const std::vector<Index>& slot = line_slot_;
  std::vector<double>& blocks = level->line_inverse;
  blocks.assign(line_offset_.back(), 0.0);
  const auto line_block = [&](Index k) {
    const std::size_t l = static_cast<std::size_t>(k / layers_);
    const Eigen::Index m = 3 * (line_start_[l + 1] - line_start_[l]);
    return Eigen::Map<Eigen::MatrixXd>(blocks.data() + line_offset_[l], m, m);
  };
  std::vector<std::pair<Index, Vec3>> members;
  for (Index i = 0; i < disc.num_nodes(); ++i) {
    members.clear();
    members.push_back({i, disc.self_d()[static_cast<std::size_t>(i)]});
    for (Index e = P.row_start[i]; e < P.row_start[i + 1]; ++e)
      members.push_back({P.col[static_cast<std::size_t>(e)], P.d[static_cast<std::size_t>(e)]});
    const Mat9& C = level->tangents[static_cast<std::size_t>(i)];
    for (const auto& [a, da] : members) {
      const Index sa = slot[static_cast<std::size_t>(a)];
      if (sa < 0) continue;
      auto B = line_block(a);
      for (const auto& [b, db] : members)
        if (const Index sb = slot[static_cast<std::size_t>(b)]; sb >= 0 && b / layers_ == a / layers_)
          B.block<3, 3>(3 * sa, 3 * sb) += tangent_block(C, da, db);
    }
  }
  for (Index k : line_nodes_) {
    auto B = line_block(k);
    const Index a = slot[static_cast<std::size_t>(k)];
    B.block<3, 3>(3 * a, 3 * a).diagonal().array() += shift_[static_cast<std::size_t>(k)];
    if (stab_rows_.rows() == 0) continue;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor, int>::InnerIterator it(stab_rows_, k); it; ++it)
      if (const Index b = slot[static_cast<std::size_t>(it.col())];
          b >= 0 && it.col() / layers_ == k / layers_)
        B.block<3, 3>(3 * a, 3 * b).diagonal().array() += it.value();
  }
  for (std::size_t l = 0; l < lines; ++l) {
    const Eigen::Index m = 3 * (line_start_[l + 1] - line_start_[l]);
    if (m == 0) continue;
    Eigen::Map<Eigen::MatrixXd> B(blocks.data() + line_offset_[l], m, m);
    const Eigen::LLT<Eigen::MatrixXd> llt(B);
    if (llt.info() != Eigen::Success)
      throw NumericalError("wall multigrid: a through-wall line's block is not positive definite");
    B = llt.solve(Eigen::MatrixXd::Identity(m, m));
  }
  galerkin_->assemble(level->tangents, level->coarse_matrix);
  if (!level->coarse.analysed()) level->coarse.analyse(level->coarse_matrix);
  level->coarse.factorize(level->coarse_matrix);
  level->build_s = clock.seconds();
  return level;
}

std::unique_ptr<WallMultigrid::Level> WallMultigrid::install(std::unique_ptr<Level> level) {
  std::swap(level, level_);
  version_ = next_version();  // not at every window: the compliance caches then hold until the next level
  ++levels_built_;
  return level;
}

namespace {
std::vector<Index> samples_in_contact(const EmbeddedContact* contact) {
  std::vector<Index> samples;
  if (contact != nullptr)
    contact->for_each_contact([&](Index v, double, const Vec3&) { samples.push_back(v); });
  std::sort(samples.begin(), samples.end());
  return samples;
}
}  // namespace

void WallMultigrid::follow_state(const Vec3Array& x) {
  if (embedded_ != nullptr && samples_in_contact(embedded_) != window_samples_) {
    prepare_window(x);
    ++windows_followed_;
  }
}

void WallMultigrid::prepare_window(const Vec3Array& x) {
  window_samples_ = samples_in_contact(embedded_);
  const Stopwatch watch;
  struct Log {
    const Stopwatch& w;
    const std::vector<Index>& nodes;
    ~Log() {
      spdlog::debug("wall multigrid: window of {} nodes prepared in {:.2f} ms", nodes.size(),
                    w.seconds() * 1e3);
    }
  } log{watch, window_};
  const Discretization& disc = problem_.discretization();
  for (Index k : window_) window_slot_[static_cast<std::size_t>(k)] = -1;
  window_.clear();
  window_contacts_.clear();
  if (!contacts_.empty() || embedded_ != nullptr) {
    // Whole through-wall lines, so that the smoothing outside never splits one.
    for (std::size_t l = 0; l + 1 < line_start_.size(); ++l) {
      bool near = false;
      for (Index a = line_start_[l]; !near && a < line_start_[l + 1]; ++a) {
        const Index k = line_nodes_[static_cast<std::size_t>(a)];
        near = contacts_.in_contact(k);
        for (std::size_t o = 0; !near && o < problem_.tools().size(); ++o)
          near = obstacle_contact(embedded_ ? embedded_->geometry(o) : contacts_.geometry(o),
                                  x[static_cast<std::size_t>(k)])
                     .value < window_m_;
      }
      if (!near) continue;
      for (Index a = line_start_[l]; a < line_start_[l + 1]; ++a) {
        const Index k = line_nodes_[static_cast<std::size_t>(a)];
        window_slot_[static_cast<std::size_t>(k)] = static_cast<Index>(window_.size());
        window_.push_back(k);
      }
    }
  }
  if (window_.empty()) return;
  // The energies whose stencils reach the window: its nodes and every node that has one of them as neighbour.
  const PairTable& P = disc.pairs();
  const PairTable& T = disc.transposed();
  window_energies_.clear();
  std::vector<char> seen(static_cast<std::size_t>(disc.num_nodes()), 0);
  for (Index k : window_) {
    if (!seen[static_cast<std::size_t>(k)])
      seen[static_cast<std::size_t>(k)] = 1, window_energies_.push_back(k);
    for (Index e = T.row_start[k]; e < T.row_start[k + 1]; ++e) {
      const Index i = T.col[static_cast<std::size_t>(e)];
      if (!seen[static_cast<std::size_t>(i)])
        seen[static_cast<std::size_t>(i)] = 1, window_energies_.push_back(i);
    }
  }
  energy_tangents(problem_.energy(), x, projection_, window_tangents_, &window_energies_);
  const Eigen::Index m = static_cast<Eigen::Index>(window_.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3 * m, 3 * m);
  // Only the lower triangle (block rows a >= b) is assembled: the factor reads no more. Node i's energy
  // couples its stencil's members k, l by sum_{c,d} C[(.,c),(.,d)] d_ik[c] d_il[d]; contracting C with d_ik
  // once per member (U_k, 3 x 9) leaves 27 products per pair instead of tangent_block's 108.
  std::vector<std::pair<Index, Vec3>> members;
  std::vector<Eigen::Matrix<double, 3, 9>> U;
  for (Index i : window_energies_) {
    members.clear();
    if (const Index s = window_slot_[static_cast<std::size_t>(i)]; s >= 0)
      members.push_back({s, disc.self_d()[static_cast<std::size_t>(i)]});
    for (Index e = P.row_start[i]; e < P.row_start[i + 1]; ++e)
      if (const Index s = window_slot_[static_cast<std::size_t>(P.col[static_cast<std::size_t>(e)])]; s >= 0)
        members.push_back({s, P.d[static_cast<std::size_t>(e)]});
    const Mat9& C = window_tangents_[static_cast<std::size_t>(i)];
    U.resize(members.size());
    for (std::size_t k = 0; k < members.size(); ++k) {
      const Vec3& d = members[k].second;
      U[k] = d[0] * C.middleRows<3>(0) + d[1] * C.middleRows<3>(3) + d[2] * C.middleRows<3>(6);
    }
    for (std::size_t k = 0; k < members.size(); ++k)
      for (std::size_t l = 0; l < members.size(); ++l) {
        const Index a = members[k].first, b = members[l].first;
        if (a < b) continue;
        const Vec3& d = members[l].second;
        A.block<3, 3>(3 * a, 3 * b) +=
            d[0] * U[k].middleCols<3>(0) + d[1] * U[k].middleCols<3>(3) + d[2] * U[k].middleCols<3>(6);
      }
  }
  for (Eigen::Index a = 0; a < m; ++a) {
    const Index k = window_[static_cast<std::size_t>(a)];
    A.block<3, 3>(3 * a, 3 * a).diagonal().array() += shift_[static_cast<std::size_t>(k)];
    if (stab_rows_.rows() == 0) continue;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor, int>::InnerIterator it(stab_rows_, k); it; ++it)
      if (const Index b = window_slot_[static_cast<std::size_t>(it.col())]; b >= 0)
        A.block<3, 3>(3 * a, 3 * b).diagonal().array() += it.value();
  }
  if (embedded_) {
    // The penalty couples the nodes of each penetrating sample: phi_vi phi_vj K_v.
    const ContactSurface& S = embedded_->surface();
    embedded_->for_each_contact([&](Index v, double k, const Vec3& normal) {
      const Mat3 K = k * normal * normal.transpose();
      for (Index p = S.row_start[v]; p < S.row_start[v + 1]; ++p) {
        const Index a = window_slot_[static_cast<std::size_t>(S.col[static_cast<std::size_t>(p)])];
        if (a < 0) continue;
        for (Index q = S.row_start[v]; q < S.row_start[v + 1]; ++q)
          if (const Index b = window_slot_[static_cast<std::size_t>(S.col[static_cast<std::size_t>(q)])];
              b >= 0)
            A.block<3, 3>(3 * a, 3 * b) +=
                (S.val[static_cast<std::size_t>(p)] * S.val[static_cast<std::size_t>(q)]) * K;
      }
    });
  }
  if (!window_factor_.compute(std::move(A)))
    throw NumericalError("wall multigrid: the window's block of the Newton matrix is not positive definite");
}

void WallMultigrid::update_window_contacts() const {
  // The contacts in the window hold their normal displacement: the window's solve is projected onto n . z = 0
  // there by a Woodbury correction of its factor (recomputed when the set or a normal changed).
  std::vector<Index> contacts;
  Vec3Array normals;
  for (Index k : window_)
    if (contacts_.in_contact(k)) contacts.push_back(k), normals.push_back(contacts_.normal(k));
  bool same = contacts == window_contacts_ && normals.size() == window_normals_.size();
  for (std::size_t c = 0; same && c < normals.size(); ++c) same = normals[c] == window_normals_[c];
  if (same) return;
  window_contacts_ = std::move(contacts);
  window_normals_ = std::move(normals);
  const Eigen::Index m = static_cast<Eigen::Index>(window_.size()),
                     mc = static_cast<Eigen::Index>(window_contacts_.size());
  if (mc == 0) return;
  Eigen::MatrixXd Nt = Eigen::MatrixXd::Zero(3 * m, mc);
  for (Eigen::Index c = 0; c < mc; ++c)
    Nt.block<3, 1>(3 * window_slot_[static_cast<std::size_t>(window_contacts_[static_cast<std::size_t>(c)])],
                   c) = window_normals_[static_cast<std::size_t>(c)];
  window_Z_ = window_factor_.solve(Nt);
  window_NZ_.compute(Nt.transpose() * window_Z_);
}

void WallMultigrid::smooth(const Vec3Array& b, Vec3Array& z, bool constrained) const {
  z.assign(b.size(), Vec3::Zero());
  const double w = options_.jacobi_damping;
  // Line Jacobi outside the window (prepare_window takes whole lines): the wall is stiffer through its
  // thickness than along it, so a node's block alone leaves the through-wall error to the coarse level.
  std::vector<double> bl;
  for (std::size_t l = 0; l + 1 < line_start_.size(); ++l) {
    const Index first = line_start_[l], nodes = line_start_[l + 1] - first;
    if (nodes == 0 ||
        window_slot_[static_cast<std::size_t>(line_nodes_[static_cast<std::size_t>(first)])] >= 0)
      continue;
    const std::size_t m = static_cast<std::size_t>(3 * nodes);
    bl.resize(m);
    bool zero = true;
    for (Index a = 0; a < nodes; ++a) {
      const Vec3& v = b[static_cast<std::size_t>(line_nodes_[static_cast<std::size_t>(first + a)])];
      for (int c = 0; c < 3; ++c) bl[3 * static_cast<std::size_t>(a) + static_cast<std::size_t>(c)] = v[c];
      zero = zero && v.isZero(0.0);
    }
    if (zero) {  // (the haptic hand-off's columns are zero on all but a few lines)
      for (Index a = 0; a < nodes; ++a)
        z[static_cast<std::size_t>(line_nodes_[static_cast<std::size_t>(first + a)])].setZero();
      continue;
    }
    // z = w A^{-1} b on the line (column-major, a few dozen entries: plain loops beat Eigen's dynamic ones).
    const double* inv = level_->line_inverse.data() + line_offset_[l];
    for (Index a = 0; a < nodes; ++a) {
      Vec3& out = z[static_cast<std::size_t>(line_nodes_[static_cast<std::size_t>(first + a)])];
      for (int c = 0; c < 3; ++c) {
        const std::size_t row = 3 * static_cast<std::size_t>(a) + static_cast<std::size_t>(c);
        double sum = 0.0;
        for (std::size_t j = 0; j < m; ++j) sum += inv[j * m + row] * bl[j];
        out[c] = w * sum;
      }
    }
  }
  if (window_.empty()) return;
  const Eigen::Index m = static_cast<Eigen::Index>(window_.size());
  wb_.resize(3 * m);
  for (Eigen::Index a = 0; a < m; ++a)
    wb_.segment<3>(3 * a) = b[static_cast<std::size_t>(window_[static_cast<std::size_t>(a)])];
  Eigen::VectorXd y = window_factor_.solve(wb_);
  if (constrained && !window_contacts_.empty()) {
    Eigen::VectorXd ny(static_cast<Eigen::Index>(window_contacts_.size()));
    for (std::size_t c = 0; c < window_contacts_.size(); ++c)
      ny[static_cast<Eigen::Index>(c)] = window_normals_[c].dot(
          y.segment<3>(3 * window_slot_[static_cast<std::size_t>(window_contacts_[c])]));
    y -= window_Z_ * window_NZ_.solve(ny);
  }
  for (Eigen::Index a = 0; a < m; ++a)
    z[static_cast<std::size_t>(window_[static_cast<std::size_t>(a)])] = y.segment<3>(3 * a);
}

void WallMultigrid::update_coarse_contacts() const {
  // Every contact, in the window or not (the solver's active set), with today's normals. (Tools on the wall's
  // surface have none: their penalty held as constraints here took 30 % more CG iterations on the real-time
  // vein.)
  std::vector<Index> contacts;
  Vec3Array normals;
  for (Index k : free_.nodes)
    if (contacts_.in_contact(k)) contacts.push_back(k), normals.push_back(contacts_.normal(k));
  bool same = contacts == coarse_contacts_ && normals.size() == coarse_normals_.size() &&
              coarse_contacts_version_ == version_;
  for (std::size_t c = 0; same && c < normals.size(); ++c) same = normals[c] == coarse_normals_[c];
  if (same) return;
  coarse_contacts_ = std::move(contacts);
  coarse_normals_ = std::move(normals);
  coarse_contacts_version_ = version_;
  const Eigen::Index mc = static_cast<Eigen::Index>(coarse_contacts_.size());
  if (mc == 0) return;
  coarse_G_ = Eigen::MatrixXd::Zero(3 * static_cast<Eigen::Index>(prolongation_.coarse_nodes), mc);  // G^T
  for (Eigen::Index c = 0; c < mc; ++c) {
    const Index k = coarse_contacts_[static_cast<std::size_t>(c)];
    for (auto e = prolongation_.row_start[static_cast<std::size_t>(k)];
         e < prolongation_.row_start[static_cast<std::size_t>(k) + 1]; ++e)
      coarse_G_.block<3, 1>(3 * prolongation_.coarse[static_cast<std::size_t>(e)], c) +=
          prolongation_.weight[static_cast<std::size_t>(e)] * coarse_normals_[static_cast<std::size_t>(c)];
  }
  level_->coarse.solve(coarse_G_, coarse_Z_);
  coarse_GZ_.compute(coarse_G_.transpose() * coarse_Z_);
}

void WallMultigrid::coarse_correction(const Vec3Array& b, Vec3Array& z, bool constrained) const {
  prolongation_.restrict_to(b, cb_);
  level_->coarse.solve(cb_, cy_);
  if (constrained && !coarse_contacts_.empty()) {
    // Only coarse corrections that leave the contacts where they are: the Galerkin correction in that
    // subspace, so it never raises the error's energy however many contacts there are.
    const Eigen::VectorXd g = coarse_G_.transpose() * cy_;
    cy_ -= coarse_Z_ * coarse_GZ_.solve(g);
  }
  prolongation_.prolongate_add(cy_, z);
}

bool WallMultigrid::apply(const Vec3Array& r, Vec3Array& z) const {
  if (!level_) return false;
  b_ = r;
  contacts_.filter(b_);
  update_window_contacts();
  update_coarse_contacts();
  if (op_ == nullptr) {
    // Without the operator: the parts added (an additive two-level method).
    smooth(b_, z, true);
    coarse_correction(b_, z, true);
    contacts_.filter(z);
    return true;
  }
  // One symmetric V-cycle: z1 = S b; z2 = z1 + C (b - H z1); z = z2 + S (b - H z2).
  smooth(b_, z1_, true);
  contacts_.filter(z1_);
  (*op_)(z1_, t_);
  for (Index k : free_.nodes)
    t_[static_cast<std::size_t>(k)] = b_[static_cast<std::size_t>(k)] - t_[static_cast<std::size_t>(k)];
  contacts_.filter(t_);
  coarse_correction(t_, z1_, true);
  contacts_.filter(z1_);
  (*op_)(z1_, t_);
  for (Index k : free_.nodes)
    t_[static_cast<std::size_t>(k)] = b_[static_cast<std::size_t>(k)] - t_[static_cast<std::size_t>(k)];
  contacts_.filter(t_);
  smooth(t_, y_, true);
  z.assign(r.size(), Vec3::Zero());
  for (Index k : free_.nodes)
    z[static_cast<std::size_t>(k)] = z1_[static_cast<std::size_t>(k)] + y_[static_cast<std::size_t>(k)];
  contacts_.filter(z);
  return true;
}

bool WallMultigrid::solve_columns(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const {
  // The parts added (smoothing and the coarse correction), all columns at once through the coarse factor.
  if (!level_) return false;
  const std::size_t n = static_cast<std::size_t>(problem_.discretization().num_nodes());
  const Eigen::Index cols = B.cols();
  std::vector<Vec3Array> z(static_cast<std::size_t>(cols));
  Vec3Array b(n, Vec3::Zero());
  Eigen::VectorXd col, c;
  Eigen::MatrixXd C(3 * static_cast<Eigen::Index>(prolongation_.coarse_nodes), cols), Y;
  for (Eigen::Index j = 0; j < cols; ++j) {
    col = B.col(j);
    free_.unpack(col, b);
    smooth(b, z[static_cast<std::size_t>(j)], false);
    prolongation_.restrict_to(b, c);
    C.col(j) = c;
  }
  level_->coarse.solve(C, Y);
  X.resize(B.rows(), cols);
  for (Eigen::Index j = 0; j < cols; ++j) {
    Vec3Array& zj = z[static_cast<std::size_t>(j)];
    c = Y.col(j);
    prolongation_.prolongate_add(c, zj);
    free_.pack(zj, col);
    X.col(j) = col;
  }
  return true;
}

nlohmann::json WallMultigrid::info() const {
  nlohmann::json j = {{"matrix", "wall multigrid"},
                      {"inertia_shift", options_.inv_h2 > 0.0},
                      {"coarse_nodes", prolongation_.coarse_nodes},
                      {"coarse_blocks", galerkin_->blocks()},
                      {"window_m", window_m_},
                      {"window_nodes", window_.size()},
                      {"levels_built", levels_built_},
                      {"windows_followed", windows_followed_},
                      {"last_level_build_s", last_level_seconds()}};
  if (level_) j["coarse_nnz_l"] = level_->coarse.stats().nnz_l;
  return j;
}

}  // namespace vascsim
