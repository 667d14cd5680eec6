// The Haar distribution's tree operations: addition of two adaptive trees (their union), scaling,
// the power integral, and a versioned binary serialization that is validated on reading.
#include <glossy/haar.h>
#include <glossy/serial.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <istream>
#include <ostream>
#include <stdexcept>

namespace glossy {

int hintLevel(double width) {
  if (!(width > 0.0)) return 0;
  double cells = (0.5 * kPi) / (0.5 * width);  // want a cell no larger than half the width
  return std::max(0, static_cast<int>(std::ceil(std::log2(cells))));
}

void HaarDistribution::addToSubtree(std::uint32_t i, const float* v) {
  Node& n = nodes_[i];
  for (int c = 0; c < 3; ++c) n.rgb[c] += v[c];
  if (n.child != 0)
    for (std::uint32_t k = 0; k < 4; ++k) addToSubtree(n.child + k, v);
}

void HaarDistribution::merge(std::uint32_t i, const HaarDistribution& o, std::uint32_t j) {
  const Node& b = o.nodes_[j];
  if (b.child == 0) {
    // A constant over the other's cell: every node below adds it (inner values are cell means).
    addToSubtree(i, b.rgb);
    return;
  }
  if (nodes_[i].child == 0) {
    // This cell is a leaf where the other is refined: split it into four copies of its value.
    auto first = static_cast<std::uint32_t>(nodes_.size());
    Node copy{{nodes_[i].rgb[0], nodes_[i].rgb[1], nodes_[i].rgb[2]}, 0};
    nodes_.resize(nodes_.size() + 4, copy);
    nodes_[i].child = first;
  }
  for (int c = 0; c < 3; ++c) nodes_[i].rgb[c] += b.rgb[c];
  std::uint32_t ci = nodes_[i].child;
  for (std::uint32_t k = 0; k < 4; ++k) merge(ci + k, o, b.child + k);
}

std::uint32_t HaarDistribution::locate(const Vec3& d, FaceTri* cell, int* level, std::uint64_t* index) const {
  Bary b = octaBary(d);
  int face = octaFace(d);
  auto i = static_cast<std::uint32_t>(face);
  FaceTri t = octaRoot(face);
  int depth = 0;
  std::uint64_t number = std::uint64_t(face);
  while (nodes_[i].child != 0) {
    int k = descend(b);
    i = nodes_[i].child + static_cast<std::uint32_t>(k);
    if (cell) t = t.child(k);
    number = 4 * number + std::uint64_t(k);
    ++depth;
  }
  if (cell) *cell = t;
  if (level) *level = depth;
  if (index) *index = number;
  return i;
}

namespace {

void copyCut(const std::vector<HaarDistribution::Node>& src, std::uint32_t i, std::vector<HaarDistribution::Node>& dst,
             std::uint32_t j, int level, int maxLevel) {
  dst[j] = {{src[i].rgb[0], src[i].rgb[1], src[i].rgb[2]}, 0};
  if (src[i].child == 0 || level >= maxLevel) return;
  auto first = static_cast<std::uint32_t>(dst.size());
  dst.resize(dst.size() + 4);
  dst[j].child = first;
  for (std::uint32_t k = 0; k < 4; ++k) copyCut(src, src[i].child + k, dst, first + k, level + 1, maxLevel);
  // Four equal leaves say no more than one: fold them (they are the last four nodes written).
  const auto& c = dst[first];
  bool equal = true;
  for (std::uint32_t k = 0; k < 4 && equal; ++k) {
    const auto& x = dst[first + k];
    equal = x.child == 0 && x.rgb[0] == c.rgb[0] && x.rgb[1] == c.rgb[1] && x.rgb[2] == c.rgb[2];
  }
  if (equal && dst.size() == first + 4) {
    float v[3] = {c.rgb[0], c.rgb[1], c.rgb[2]};
    dst.resize(first);
    dst[j] = {{v[0], v[1], v[2]}, 0};
  }
}

}  // namespace

HaarDistribution HaarDistribution::truncated(int maxLevel) const {
  HaarDistribution out;
  out.nodes_.reserve(nodes_.size());
  for (std::uint32_t f = 0; f < 8; ++f) copyCut(nodes_, f, out.nodes_, f, 0, maxLevel);
  out.nodes_.shrink_to_fit();
  return out;
}

HaarDistribution HaarDistribution::fromNodes(std::vector<Node> nodes) {
  assert(nodes.size() >= 8 && (nodes.size() - 8) % 4 == 0);
  HaarDistribution d;
  d.nodes_ = std::move(nodes);
  d.nodes_.shrink_to_fit();
  return d;
}

Rgb HaarDistribution::leafIntegral() const {
  Rgb sum(0.0);
  visitLeaves([&](const FaceTri& t, int, const Rgb& v, std::uint64_t) {
    if (v != Rgb(0.0)) sum += v * t.solidAngle();
  });
  return sum;
}

Rgb HaarDistribution::peak() const {
  Rgb m(0.0);
  for (const Node& n : nodes_) m = glm::max(m, Rgb(n.rgb[0], n.rgb[1], n.rgb[2]));
  return m;
}

void HaarDistribution::add(const HaarDistribution& other) {
  for (std::uint32_t f = 0; f < 8; ++f) merge(f, other, f);
}

void HaarDistribution::scale(double s) {
  for (Node& n : nodes_)
    for (float& v : n.rgb) v = static_cast<float>(v * s);
}

Rgb HaarDistribution::integral() const {
  // Each octant subtends pi/2 sr, and a node holds the solid-angle mean of its cell.
  Rgb sum(0.0);
  for (int f = 0; f < 8; ++f) sum += Rgb(nodes_[f].rgb[0], nodes_[f].rgb[1], nodes_[f].rgb[2]);
  return 0.5 * kPi * sum;
}

std::size_t HaarDistribution::leaves() const {
  return static_cast<std::size_t>(std::count_if(nodes_.begin(), nodes_.end(), [](const Node& n) { return n.child == 0; }));
}

int HaarDistribution::depth() const {
  int d = 0;
  visitLeaves([&](const FaceTri&, int level, const Rgb&, std::uint64_t) { d = std::max(d, level); });
  return d;
}

void HaarDistribution::serialize(std::ostream& out) const {
  serial::writeHeader(out, serial::kHaarTag);
  serial::writeU64(out, nodes_.size());
  for (const Node& n : nodes_) {
    for (float v : n.rgb) serial::writeF32(out, v);
    serial::writeU32(out, n.child);
  }
}

HaarDistribution HaarDistribution::deserialize(std::istream& in) {
  serial::readHeader(in, serial::kHaarTag, "Haar distribution");
  std::uint64_t count = serial::readU64(in);
  if (count < 8 || (count - 8) % 4 != 0 || count > (std::uint64_t(1) << 32))
    throw std::runtime_error("Haar distribution: bad node count " + std::to_string(count));
  HaarDistribution d;
  d.nodes_.resize(count);
  for (Node& n : d.nodes_) {
    for (float& v : n.rgb) {
      v = serial::readF32(in);
      if (!std::isfinite(v)) throw std::runtime_error("Haar distribution: non-finite value");
    }
    n.child = serial::readU32(in);
  }
  // Every child block must lie inside the array, after its parent, and be claimed once.
  std::vector<std::uint8_t> claimed(count, 0);
  for (std::uint64_t i = 0; i < count; ++i) {
    std::uint32_t c = d.nodes_[i].child;
    if (c == 0) continue;
    if (c <= i || c < 8 || std::uint64_t(c) + 4 > count)
      throw std::runtime_error("Haar distribution: damaged tree at node " + std::to_string(i));
    for (std::uint32_t k = 0; k < 4; ++k) {
      if (claimed[c + k]) throw std::runtime_error("Haar distribution: damaged tree at node " + std::to_string(i));
      claimed[c + k] = 1;
    }
  }
  for (std::uint64_t i = 8; i < count; ++i)
    if (!claimed[i]) throw std::runtime_error("Haar distribution: orphan node " + std::to_string(i));
  return d;
}

}  // namespace glossy
