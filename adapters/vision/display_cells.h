// Joins an extension to the VISION-like host (vision_host), which speaks hr/extension.h itself
// during the solve: the adapter passes every hook through. What it adds is the display. That host's
// solution shows each leaf as small flat cells (a curved leaf as many), so the solution's elements
// are cells, not the host's nodes, and display, save and load address cells. A leaf's cells share
// its light (no copy per cell): each shows the leaf's radiance as seen at its own normal.
#pragma once
#include <hr/extension.h>
#include <hr/solution.h>

#include <memory>
#include <vector>

namespace adapters::vision {

/// The extension as the VISION-like host loads it (solve, and every reader of its solutions).
std::unique_ptr<hr::Extension> adapt(std::unique_ptr<hr::Extension> inner);

/// After the solve, before the outputs: the cells learn their leaves (cellLeaf[i]: the host leaf
/// shown by solution element i). `ext` is what adapt() made; host and sol must outlive it.
void showCells(hr::Extension& ext, const hr::HostView& host, const hr::Solution& sol,
               const std::vector<std::uint32_t>& cellLeaf);

}  // namespace adapters::vision
