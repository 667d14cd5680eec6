// The glossy extension's reflection on the sample sets of real solves, replayable and comparable
// across builds:
//   bench_reflect capture SCENE.json OUT.bin [THREADS]
//       solves the scene with Illumination Samples (default options) and records every reflect call:
//       the leaf's normal, area, material and samples, in call order per leaf.
//   bench_reflect replay IN.bin [VALUES.bin] [--every K] [--first N] [--basis B]
//       reflects the recorded calls again, serially, through glossy::IlluminationSamples on a small
//       host view of the recorded leaves: thread CPU time per reflect, BRDF evaluations and samples per
//       reflect; with VALUES.bin, every K-th call's reflected power and its intensity (luminance) at a
//       fixed set of directions over the leaf's hemisphere, for `compare`.
//   bench_reflect compare A.bin B.bin
//       A against B: relative power differences and the relative L1 distance of the intensities.
// CPU time, not wall time: the machines these run on are shared.
#include <glossy/illumination_samples.h>
#include <hr/scene.h>
#include <hr/solver.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using hr::NodeId;
using hr::Rgb;
using hr::Vec3;

double cpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

struct Call {
  std::uint32_t leaf = 0, material = 0;
  Vec3 normal{0.0};
  double area = 0.0;
  std::vector<hr::IncidentSample> samples;
};

/// Forwards every hook to the real extension and records the reflect calls.
class Recorder final : public hr::Extension {
 public:
  glossy::IlluminationSamples inner;
  const hr::HostView* view = nullptr;
  std::mutex mutex;
  std::vector<Call> calls;

  std::string_view name() const override { return inner.name(); }
  std::vector<hr::OptionSpec> options() const override { return inner.options(); }
  void configure(const std::vector<hr::OptionValue>& v) override { inner.configure(v); }
  bool simulates(const hr::MaterialInfo& m) const override { return inner.simulates(m); }
  void attach(const hr::HostView& v) override {
    view = &v;
    inner.attach(v);
  }
  void split(NodeId p, std::span<const NodeId> c) override { inner.split(p, c); }
  Rgb intensity(NodeId n, const Vec3& d) const override { return inner.intensity(n, d); }
  Rgb meanIntensity(NodeId n, std::span<const Vec3> p) const override { return inner.meanIntensity(n, p); }
  Rgb intensityBound(NodeId n, const Vec3& a, double c) const override { return inner.intensityBound(n, a, c); }
  void gather(NodeId r, std::span<const hr::IncidentSample> s) override { inner.gather(r, s); }
  void reflect(NodeId leaf, std::span<const hr::IncidentSample> s) override {
    if (!view) return inner.reflect(leaf, s);  // the host's first push comes before any attach
    hr::NodeInfo info = view->info(leaf);
    Call c{leaf.index(), info.material, info.normal, info.area, {s.begin(), s.end()}};
    {
      std::lock_guard<std::mutex> lock(mutex);
      calls.push_back(std::move(c));
    }
    inner.reflect(leaf, s);
  }
  void pull(NodeId n, std::span<const NodeId> c) override { inner.pull(n, c); }
  double powerChange() const override { return inner.powerChange(); }
  Rgb reflectedPower(NodeId l) const override { return inner.reflectedPower(l); }
  Rgb sampleExitant(NodeId l, double u1, double u2, Vec3& d) const override { return inner.sampleExitant(l, u1, u2, d); }
  Rgb radiance(NodeId l, const Vec3& e) const override { return inner.radiance(l, e); }
  std::size_t coefficients(NodeId l) const override { return inner.coefficients(l); }
  std::vector<hr::StatEntry> stats() const override { return inner.stats(); }
};

template <class T>
void put(std::ofstream& f, const T& v) {
  f.write(reinterpret_cast<const char*>(&v), sizeof v);
}
template <class T>
T get(std::ifstream& f) {
  T v{};
  f.read(reinterpret_cast<char*>(&v), sizeof v);
  if (!f) throw std::runtime_error("truncated file");
  return v;
}

struct Capture {
  std::vector<hr::MaterialInfo> materials;
  std::vector<Call> calls;
};

void save(const Capture& c, const std::string& path) {
  std::ofstream f(path, std::ios::binary);
  put(f, std::uint32_t(sizeof(hr::IncidentSample)));  // samples are raw bytes: their layout's size first
  put(f, std::uint64_t(c.materials.size()));
  for (const auto& m : c.materials) put(f, m);
  put(f, std::uint64_t(c.calls.size()));
  for (const Call& k : c.calls) {
    put(f, k.leaf), put(f, k.material), put(f, k.normal), put(f, k.area);
    put(f, std::uint64_t(k.samples.size()));
    for (const auto& s : k.samples) put(f, s);
  }
  if (!f) throw std::runtime_error("cannot write " + path);
}

Capture load(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot read " + path);
  Capture c;
  if (const auto bytes = get<std::uint32_t>(f); bytes != sizeof(hr::IncidentSample))
    throw std::runtime_error(path + ": samples of " + std::to_string(bytes) + " bytes, this build's have " +
                             std::to_string(sizeof(hr::IncidentSample)) + ": capture again");
  c.materials.resize(get<std::uint64_t>(f));
  for (auto& m : c.materials) m = get<hr::MaterialInfo>(f);
  c.calls.resize(get<std::uint64_t>(f));
  for (Call& k : c.calls) {
    k.leaf = get<std::uint32_t>(f), k.material = get<std::uint32_t>(f), k.normal = get<Vec3>(f), k.area = get<double>(f);
    k.samples.resize(get<std::uint64_t>(f));
    for (auto& s : k.samples) s = get<hr::IncidentSample>(f);
  }
  return c;
}

int capture(const std::string& scenePath, const std::string& out, int threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
  hr::Scene scene = hr::loadScene(scenePath);
  hr::TessellationReport rep;
  hr::Hierarchy hier(hr::buildPatches(scene, rep));
  hr::Visibility vis(hier.patches());
  Recorder rec;
  rec.configure({});
  hr::Solver solver(scene, hier, vis, hr::SolverOptions::from(scene.settings), &rec);
  hr::SolveStats st = solver.solve();
  Capture c;
  for (std::size_t i = 0; i < solver.view().materialCount(); ++i) c.materials.push_back(solver.view().material(std::uint32_t(i)));
  c.calls = std::move(rec.calls);
  save(c, out);
  std::printf("%s: %zu reflect calls in %d iterations recorded to %s\n", scenePath.c_str(), c.calls.size(), st.iterations,
              out.c_str());
  return 0;
}

/// The recorded leaves as planar leaf elements (dense indices) under one cluster.
class ReplayHost final : public hr::HostView {
 public:
  std::vector<hr::NodeInfo> elements;
  std::vector<NodeId> kids;
  std::vector<hr::MaterialInfo> materials;
  NodeId root() const override { return NodeId{NodeId::kClusterBit}; }
  hr::NodeInfo info(NodeId id) const override {
    if (id.isCluster()) return {};
    return elements.at(id.index());
  }
  std::span<const NodeId> children(NodeId id) const override {
    return id.isCluster() ? std::span<const NodeId>(kids) : std::span<const NodeId>();
  }
  std::size_t elementCount() const override { return elements.size(); }
  std::size_t clusterCount() const override { return 1; }
  hr::MaterialInfo material(std::uint32_t id) const override { return materials.at(id); }
  std::size_t materialCount() const override { return materials.size(); }
};

/// Fixed directions over the hemisphere of +z, equal solid angle (rings in cos theta).
std::vector<Vec3> hemisphereDirections() {
  std::vector<Vec3> d;
  const int NZ = 16, NP = 32;
  for (int i = 0; i < NZ; ++i) {
    double z = (i + 0.5) / NZ, r = std::sqrt(1.0 - z * z);
    for (int j = 0; j < NP; ++j) {
      double phi = 2.0 * hr::kPi * (j + 0.5 + 0.37 * i) / NP;
      d.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
    }
  }
  return d;
}

int replay(const std::string& in, const std::string& valuesPath, std::size_t every, std::size_t first,
           const std::vector<hr::OptionValue>& options) {
  Capture c = load(in);
  if (first > 0 && first < c.calls.size()) c.calls.resize(first);
  ReplayHost host;
  host.materials = c.materials;
  std::map<std::uint32_t, std::uint32_t> index;
  for (const Call& k : c.calls) {
    auto [it, fresh] = index.try_emplace(k.leaf, std::uint32_t(host.elements.size()));
    if (!fresh) continue;
    hr::NodeInfo n;
    n.normal = k.normal, n.area = k.area, n.planar = true, n.leaf = true, n.material = k.material, n.object = 0;
    host.elements.push_back(n);
    host.kids.push_back(NodeId{it->second});
  }
  glossy::IlluminationSamples ext;
  ext.configure(options);
  ext.attach(host);
  const std::vector<Vec3> dirs = hemisphereDirections();
  std::ofstream vf;
  if (!valuesPath.empty()) vf.open(valuesPath, std::ios::binary);
  double cpu = 0.0, samples = 0.0;
  std::size_t written = 0;
  for (std::size_t i = 0; i < c.calls.size(); ++i) {
    const Call& k = c.calls[i];
    NodeId leaf{index[k.leaf]};
    double t0 = cpuSeconds();
    ext.reflect(leaf, k.samples);
    cpu += cpuSeconds() - t0;
    samples += double(k.samples.size());
    if (vf.is_open() && i % every == 0) {
      Vec3 u, v;
      glossy::orthonormalBasis(k.normal, u, v);
      put(vf, ext.reflectedPower(leaf));
      for (const Vec3& d : dirs) put(vf, float(hr::luminance(ext.intensity(leaf, d.x * u + d.y * v + d.z * k.normal))));
      ++written;
    }
  }
  double evals = 0.0, kept = 0.0;
  for (const auto& s : ext.stats()) {
    if (s.name == "brdf_evaluations") evals = s.value;
    if (s.name == "samples_merged_away") kept -= s.value;
    if (s.name == "samples_dropped_no_front_light") kept -= s.value;
  }
  kept += samples;
  const double n = double(c.calls.size());
  std::printf("%s: %zu reflects, %.1f samples (%.1f after dropping and merging) per reflect\n", in.c_str(), c.calls.size(),
              samples / n, kept / n);
  std::printf("  reflect CPU %.3f s, %.1f us per reflect, %.0f BRDF evaluations per reflect\n", cpu, 1e6 * cpu / n, evals / n);
  if (written) std::printf("  values of %zu reflects written to %s\n", written, valuesPath.c_str());
  return 0;
}

int compare(const std::string& a, const std::string& b) {
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  const std::size_t nd = hemisphereDirections().size();
  std::vector<float> va(nd), vb(nd);
  std::vector<double> powerErr, l1;
  double diffAll = 0.0, normAll = 0.0;
  while (fa.peek() != EOF && fb.peek() != EOF) {
    Rgb pa = get<Rgb>(fa), pb = get<Rgb>(fb);
    for (auto& x : va) x = get<float>(fa);
    for (auto& x : vb) x = get<float>(fb);
    double la = hr::luminance(pa), lb = hr::luminance(pb);
    if (lb > 0.0) powerErr.push_back(std::abs(la / lb - 1.0));
    double d = 0.0, nrm = 0.0;
    for (std::size_t k = 0; k < nd; ++k) d += std::abs(double(va[k]) - vb[k]), nrm += std::abs(double(vb[k]));
    if (nrm > 0.0) l1.push_back(d / nrm);
    diffAll += d, normAll += nrm;
  }
  auto pct = [](std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(q * double(v.size())))];
  };
  std::printf("%zu reflects: power |A/B - 1| median %.2e, 99%% %.2e, max %.2e\n", powerErr.size(), pct(powerErr, 0.5),
              pct(powerErr, 0.99), pct(powerErr, 1.0));
  std::printf("  intensity relative L1 per reflect median %.2e, 99%% %.2e, max %.2e; over all %.2e\n", pct(l1, 0.5),
              pct(l1, 0.99), pct(l1, 1.0), normAll > 0.0 ? diffAll / normAll : 0.0);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::vector<std::string> a(argv + 1, argv + argc);
    if (a.size() >= 3 && a[0] == "capture") return capture(a[1], a[2], a.size() > 3 ? std::stoi(a[3]) : 2);
    if (a.size() >= 2 && a[0] == "replay") {
      std::string values;
      std::size_t every = 1, first = 0;
      std::vector<hr::OptionValue> options;
      for (std::size_t i = 2; i < a.size(); ++i) {
        if (a[i] == "--every" && i + 1 < a.size()) every = std::max<std::size_t>(1, std::stoul(a[++i]));
        else if (a[i] == "--first" && i + 1 < a.size()) first = std::stoul(a[++i]);
        else if (a[i].rfind("--", 0) == 0 && i + 1 < a.size()) options.push_back({a[i].substr(2), a[i + 1]}), ++i;
        else values = a[i];
      }
      return replay(a[1], values, every, first, options);
    }
    if (a.size() == 3 && a[0] == "compare") return compare(a[1], a[2]);
    std::fprintf(stderr,
                 "usage: bench_reflect capture SCENE.json OUT.bin [THREADS]\n"
                 "       bench_reflect replay IN.bin [VALUES.bin] [--every K] [--first N] [--OPTION VALUE...]\n"
                 "       bench_reflect compare A.bin B.bin\n");
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_reflect: %s\n", e.what());
    return 1;
  }
}
