// The two triangle rules in barycentric form, their placement on octahedron cells (Jacobian of the
// central projection, normalised to the exact solid angle) and the per-level tables of the upper cells.
#include <glossy/cell_rules.h>

#include <array>
#include <cassert>
#include <memory>
#include <mutex>

namespace glossy {

namespace {

struct Rule {
  int count = 0;
  double b[16][3];
  double w[16];
  void add(double a, double b0, double c, double weight) {
    b[count][0] = a, b[count][1] = b0, b[count][2] = c, w[count] = weight;
    ++count;
  }
  void add3(double a, double c, double weight) {  // (a, a, c) and its permutations
    add(a, a, c, weight), add(a, c, a, weight), add(c, a, a, weight);
  }
  void add6(double a, double b0, double c, double weight) {
    add(a, b0, c, weight), add(a, c, b0, weight), add(b0, a, c, weight);
    add(b0, c, a, weight), add(c, a, b0, weight), add(c, b0, a, weight);
  }
};

Rule radon7() {
  // Radon (1948): degree 5, positive weights, all points inside.
  Rule r;
  const double s = std::sqrt(15.0);
  r.add(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, 9.0 / 40.0);
  r.add3((6.0 - s) / 21.0, (9.0 + 2.0 * s) / 21.0, (155.0 - s) / 1200.0);
  r.add3((6.0 + s) / 21.0, (9.0 - 2.0 * s) / 21.0, (155.0 + s) / 1200.0);
  return r;
}

Rule dunavant16() {
  // Dunavant (1985), degree 8: positive weights, all points inside.
  Rule r;
  r.add(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, 0.144315607677787);
  r.add3(0.459292588292723, 0.081414823414554, 0.095091634267285);
  r.add3(0.170569307751760, 0.658861384496480, 0.103217370534718);
  r.add3(0.050547228317031, 0.898905543365938, 0.032458497623198);
  r.add6(0.263112829634638, 0.728492392955404, 0.008394777409958, 0.027230314174435);
  return r;
}

const Rule& rule(CellRule r) {
  static const Rule rules[2] = {radon7(), dunavant16()};
  return rules[int(r)];
}

constexpr int kLevels = UpperCells::kTableLevel + 1;

}  // namespace

void cellPoints(const FaceTri& t, CellRule which, CellPoints& out) {
  const Rule& r = rule(which);
  double x[16], y[16], z[16], w[16], sum = 0.0;
  for (int k = 0; k < r.count; ++k) {
    Vec3 p = r.b[k][0] * t.p[0] + r.b[k][1] * t.p[1] + r.b[k][2] * t.p[2];
    double len = glm::length(p);
    x[k] = p.x / len, y[k] = p.y / len, z[k] = p.z / len;
    w[k] = r.w[k] / (len * len * len);  // the Jacobian of the central projection, up to a constant
    sum += w[k];
  }
  const double scale = t.solidAngle() / sum;
  const int blocks = ruleBlocks(which);
  for (int k = 0; k < blocks * kBlockPoints; ++k) {
    double* b = out.block[k / kBlockPoints];
    const int j = k % kBlockPoints;
    const bool real = k < r.count;
    b[j] = real ? x[k] : x[0];
    b[kBlockPoints + j] = real ? y[k] : y[0];
    b[2 * kBlockPoints + j] = real ? z[k] : z[0];
    b[3 * kBlockPoints + j] = real ? w[k] * scale * std::max(0.0, z[k]) : 0.0;
  }
}

FaceTri UpperCells::cell(int level, std::uint64_t index) {
  const int shift = 2 * level;
  FaceTri t = octaRoot(int(index >> shift));
  for (int l = level - 1; l >= 0; --l) t = t.child(int((index >> (2 * l)) & 3u));
  return t;
}

const std::vector<CellCap>& UpperCells::caps(int level) {
  assert(level >= 0 && level < kLevels);
  static std::once_flag once[kLevels];
  static std::unique_ptr<std::vector<CellCap>> tables[kLevels];
  std::call_once(once[level], [level] {
    auto c = std::make_unique<std::vector<CellCap>>();
    const std::uint64_t count = 4ull << (2 * level);
    c->reserve(count);
    for (std::uint64_t i = 0; i < count; ++i) {
      FaceTri t = cell(level, i);
      Cap cap = Cap::around(t);
      c->push_back({cap.centre.x, cap.centre.y, cap.centre.z, cap.cosR, cap.sinR, t.solidAngle()});
    }
    tables[level] = std::move(c);
  });
  return *tables[level];
}

const CellCap* UpperCells::capsOf(int level) {
  static const auto tables = [] {
    std::array<const CellCap*, kTableLevel + 1> t{};
    for (int l = 0; l <= kTableLevel; ++l) t[std::size_t(l)] = caps(l).data();
    return t;
  }();
  assert(level >= 0 && level <= kTableLevel);
  return tables[std::size_t(level)];
}

const std::vector<double>& UpperCells::points(int level, CellRule which) {
  assert(level >= 0 && level < kLevels);
  static std::once_flag once[2][kLevels];
  static std::unique_ptr<std::vector<double>> tables[2][kLevels];
  const int ri = int(which);
  std::call_once(once[ri][level], [level, which, ri] {
    auto p = std::make_unique<std::vector<double>>();
    const std::uint64_t count = 4ull << (2 * level);
    const int blocks = ruleBlocks(which);
    p->reserve(count * std::uint64_t(blocks) * kBlockDoubles);
    CellPoints cp;
    for (std::uint64_t i = 0; i < count; ++i) {
      cellPoints(cell(level, i), which, cp);
      for (int b = 0; b < blocks; ++b) p->insert(p->end(), cp.block[b], cp.block[b] + kBlockDoubles);
    }
    tables[ri][level] = std::move(p);
  });
  return *tables[ri][level];
}

}  // namespace glossy
