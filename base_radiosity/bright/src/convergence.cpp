// Anderson acceleration of the sweeps over a fixed set of links (Anderson 1965; Walker and Ni 2011).
// With links fixed, one sweep (gather + push/pull) is an affine map T of the leaves' irradiance x:
// x -> E + K R x. Plain sweeps are Jacobi iterations and shrink the error by the albedo per sweep.
// Anderson mixing takes the next iterate as the combination of the last sweeps' results whose
// residuals (T(x) - x) combine to the smallest one; for a linear map this is GMRES in disguise
// (Walker and Ni, Thm. 2.2), so the dominant, nearly uniform mode of a white room (eigenvalue ~rho)
// is removed within a few sweeps instead of ~1/(1 - rho). It needs only the sweep itself, no
// transposed operator (gathering with clusters and visibility is not symmetric), and a few leaf
// vectors of memory. Channels are independent linear systems and are mixed separately.
//
// Every sum here (dot products, residuals, the power of inner nodes) runs serially in a fixed order,
// so the iterates are the same bits whatever the thread count; only the work per leaf or per node
// that writes its own entry runs in parallel (serially it made a sixth of what stayed serial in a
// two-thread solve of the Soda Shoppe).
#include "convergence.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "counting_sort.h"

namespace hr::detail {

namespace {

/// Luminance of the per-channel magnitudes: a residual that colours cannot cancel.
double absLuminance(const Rgb& c) { return luminance(glm::abs(c)); }

/// f(i) for i in [0, n), in parallel: f writes entry i of its arrays and nothing else.
template <class F>
void forEach(std::size_t n, F f) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 2048), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) f(i);
  });
}

/// Least squares min |f - sum_j gamma_j a_j| over the columns a_j (weighted already), by modified
/// Gram-Schmidt QR with one re-orthogonalisation, newest column first; a column whose remainder is
/// below 1e-10 of its norm (nearly a combination of newer ones, as old differences become near
/// convergence) is left out with gamma_j = 0. Not the normal equations: squaring the condition
/// number hid the slow, nearly uniform mode of a white room (its share of a difference is about
/// 1 - rho of the fast modes'), and sweeps stalled until the old columns left the window.
std::vector<double> leastSquares(const std::vector<std::vector<double>>& a, const std::vector<double>& f) {
  const std::size_t m = a.size(), n = f.size();
  std::vector<double> gamma(m, 0.0);
  std::vector<std::vector<double>> q;       // orthonormal columns, in elimination order
  std::vector<std::size_t> sel;             // their column indices
  std::vector<std::vector<double>> r;       // r[k][t]: coefficient of q_t in column sel[k] (t <= k)
  auto dotv = [n](const std::vector<double>& u, const std::vector<double>& v) {
    double s = 0.0;
    for (std::size_t i = 0; i < n; ++i) s += u[i] * v[i];
    return s;
  };
  for (std::size_t j = m; j-- > 0;) {
    std::vector<double> v = a[j];
    const double norm0 = std::sqrt(dotv(v, v));
    if (!(norm0 > 0.0)) continue;
    std::vector<double> coef(q.size() + 1, 0.0);
    for (int pass = 0; pass < 2; ++pass)
      for (std::size_t t = 0; t < q.size(); ++t) {
        double c = dotv(q[t], v);
        coef[t] += c;
        forEach(n, [&](std::size_t i) { v[i] -= c * q[t][i]; });
      }
    const double norm = std::sqrt(dotv(v, v));
    if (!(norm > 1e-10 * norm0)) continue;
    forEach(n, [&](std::size_t i) { v[i] /= norm; });
    coef[q.size()] = norm;
    q.push_back(std::move(v));
    r.push_back(std::move(coef));
    sel.push_back(j);
  }
  // R gamma = Q^T f, R upper triangular in elimination order (r[k][t], t <= k, is R(t, k)).
  const std::size_t k = q.size();
  std::vector<double> z(k), y(k);
  for (std::size_t t = 0; t < k; ++t) z[t] = dotv(q[t], f);
  for (std::size_t t = k; t-- > 0;) {
    double v = z[t];
    for (std::size_t u = t + 1; u < k; ++u) v -= r[u][t] * y[u];
    y[t] = v / r[t][t];
  }
  for (std::size_t t = 0; t < k; ++t) gamma[sel[t]] = y[t];
  return gamma;
}

}  // namespace

Accelerator::Accelerator(SolverState& s, int depth) : s_(s), depth_(s.ext ? 0 : std::max(depth, 0)) {}

void Accelerator::restart() {
  collectLeaves();
  std::vector<Rgb> now(leaves_.size());
  forEach(leaves_.size(), [&](std::size_t k) { now[k] = s_.Et[leaves_[k]]; });
  nodePower(now, Pref_);
  slack_ = std::min(s_.opt.eps, kPowerSlack) * s_.emittedPower;
  havePrev_ = false;
  dF_.clear();
  dG_.clear();
  prevRes_ = 0.0;
  capped_ = false;
}

void Accelerator::collectLeaves() {
  leaves_.clear();
  const auto& els = s_.h.elements();
  for (std::uint32_t i = 0; i < els.size(); ++i)
    if (els[i].leaf()) leaves_.push_back(i);
  w_.resize(leaves_.size());
  forEach(leaves_.size(), [&](std::size_t k) {
    const Rgb& rho = s_.mat(leaves_[k]).diffuse;
    w_[k] = s_.openArea(leaves_[k]) * rho * rho;
  });
  clusterLinks_.clear();
  if (!enabled()) return;
  // A stable sort with one key, the rest left out: the cluster receivers' links in link order.
  clusterLinks_.resize(s_.links.size());
  auto key = [&](std::size_t i) { return s_.links[i].receiver.isCluster() ? std::size_t(0) : std::size_t(1); };
  auto place = [&](std::size_t i, std::uint32_t p) { clusterLinks_[p] = std::uint32_t(i); };
  clusterLinks_.resize(countingSort(s_.links.size(), 1, key, place).back());
}

double Accelerator::sweep() {
  if (leaves_.empty()) collectLeaves();
  const std::size_t n = leaves_.size();
  x_.resize(n);
  g_.resize(n);
  forEach(n, [&](std::size_t k) { x_[k] = s_.Et[leaves_[k]]; });
  gatherLinks(s_);
  pushPull(s_);
  std::vector<double> change(n);
  forEach(n, [&](std::size_t k) {
    g_[k] = s_.Et[leaves_[k]];
    const std::uint32_t e = leaves_[k];
    change[k] = s_.openArea(e) * absLuminance(s_.mat(e).diffuse * (g_[k] - x_[k]));
  });
  double res = 0.0;
  for (double c : change) res += c;
  if (s_.ext) res += s_.ext->powerChange();  // the extension's light converges too
  last_ = res;
  return res;
}

void Accelerator::nodePower(const std::vector<Rgb>& x, std::vector<double>& P) const {
  const auto& els = s_.h.elements();
  const std::size_t E = els.size();
  P.assign(E + s_.h.clusters().size(), 0.0);
  forEach(leaves_.size(), [&](std::size_t k) {
    const std::uint32_t e = leaves_[k];
    P[e] = s_.openArea(e) * luminance(s_.emitted(e) + s_.mat(e).diffuse * x[k]);
  });
  // Children come after their parents (Hierarchy::subdivide appends): a reverse sweep sums them up.
  for (std::size_t e = E; e-- > 0;)
    if (els[e].parent != kNone) P[els[e].parent] += P[e];
  // A cluster's power: its patches' (root element p is patch p), by prefix sums in cluster order.
  const auto& order = s_.h.patchOrder();
  std::vector<double> prefix(order.size() + 1, 0.0);
  for (std::size_t i = 0; i < order.size(); ++i) prefix[i + 1] = prefix[i] + P[order[i]];
  forEach(s_.h.clusters().size(), [&](std::size_t c) {
    const Cluster& cl = s_.h.cluster(static_cast<std::uint32_t>(c));
    P[E + c] = prefix[cl.patchEnd] - prefix[cl.patchBegin];
  });
}

double Accelerator::allowedStep(const std::vector<double>& Pg, const std::vector<double>& Px) const {
  double t = 1.0;
  for (std::size_t n = 0; n < Pg.size(); ++n) {
    const double cap = kGrowthPerPass * Pref_[n] + slack_;
    if (Pg[n] > cap) return 0.0;
    if (Px[n] > cap) t = std::min(t, (cap - Pg[n]) / (Px[n] - Pg[n]));
  }
  return t;
}

bool Accelerator::extrapolate() {
  if (!enabled()) return false;
  // The state is now the plain result g of a sweep from x. Safeguard: a step that left a larger
  // residual than the one before it (a secant step through a spread spectrum can overshoot) is
  // undone: back to the previous sweep's plain result, history forgotten. Refinement only ever
  // sees plain sweep results, never an unchecked extrapolation.
  if (prevRes_ > 0.0 && last_ > prevRes_) {
    havePrev_ = false;
    dF_.clear(), dG_.clear();
    prevRes_ = 0.0;
    setLeafIrradiance(gPrev_);
    return !capped_;
  }
  if (capped_) return false;  // the capped step checked out: the pass ends on its plain result
  std::vector<double> Pg, Px;
  nodePower(g_, Pg);
  if (allowedStep(Pg, Pg) <= 0.0) return false;  // some sender outgrew its links already: refine
  prevRes_ = last_;
  mix(x_, g_);
  nodePower(x_, Px);
  const double t = allowedStep(Pg, Px);
  if (t < 1.0) {
    // Only part of the way: the links must be refined for the brighter light first (header).
    // One more sweep checks the step, and the pass ends on its plain result.
    forEach(x_.size(), [&](std::size_t k) { x_[k] = g_[k] + t * (x_[k] - g_[k]); });
    capped_ = true;
  }
  setLeafIrradiance(x_);
  return true;
}

void Accelerator::mix(std::vector<Rgb>& x, const std::vector<Rgb>& g) {
  const std::size_t n = x.size();
  std::vector<Rgb> f(n);
  forEach(n, [&](std::size_t k) { f[k] = g[k] - x[k]; });
  if (havePrev_) {
    if (static_cast<int>(dF_.size()) == depth_) {
      dF_.erase(dF_.begin());
      dG_.erase(dG_.begin());
    }
    std::vector<Rgb> df(n), dg(n);
    forEach(n, [&](std::size_t k) { df[k] = f[k] - fPrev_[k], dg[k] = g[k] - gPrev_[k]; });
    dF_.push_back(std::move(df));
    dG_.push_back(std::move(dg));
  }
  fPrev_ = f;
  gPrev_ = g;
  havePrev_ = true;
  const std::size_t m = dF_.size();
  x = g;  // the plain sweep's result, corrected below
  std::vector<std::vector<double>> a(m, std::vector<double>(n));
  std::vector<double> fw(n);
  for (int c = 0; c < 3 && m > 0; ++c) {
    forEach(n, [&](std::size_t k) {
      const double sw = std::sqrt(w_[k][c]);
      fw[k] = sw * f[k][c];
      for (std::size_t j = 0; j < m; ++j) a[j][k] = sw * dF_[j][k][c];
    });
    std::vector<double> gamma = leastSquares(a, fw);
    // Each entry takes the columns in the same order as before: the same bits.
    forEach(n, [&](std::size_t k) {
      for (std::size_t j = 0; j < m; ++j)
        if (gamma[j] != 0.0) x[k][c] -= gamma[j] * dG_[j][k][c];
    });
  }
  // The solution is non-negative and the sweep is monotone, so clipping an extrapolated
  // undershoot at zero only moves the iterate toward it; radiosity then never goes negative.
  forEach(n, [&](std::size_t k) { x[k] = glm::max(x[k], Rgb(0.0)); });
}

void Accelerator::setLeafIrradiance(const std::vector<Rgb>& x) {
  // Push/pull sets each leaf's irradiance to what its ancestors' links push down plus its own
  // gathered light, radiosity to emission + rho * irradiance, and pulls radiosity and cluster
  // tables up. With no light on inner nodes or clusters and x as the leaves' own, it is the
  // consistent pull of x. (The next sweep's gather overwrites both arrays.)
  std::fill(s_.Eg.begin(), s_.Eg.end(), Rgb(0.0));
  forEach(leaves_.size(), [&](std::size_t k) { s_.Eg[leaves_[k]] = x[k]; });
  forEach(clusterLinks_.size(), [&](std::size_t i) { s_.links[clusterLinks_[i]].E = glm::vec3(0.0f); });
  pushPull(s_);
}

}  // namespace hr::detail
