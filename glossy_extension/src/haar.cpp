// The Haar distribution's tree operations: addition of two adaptive trees (their union), scaling,
// the power integral, and a versioned binary serialization that is validated on reading.
#include <glossy/haar.h>
#include <glossy/serial.h>

#include <algorithm>
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
