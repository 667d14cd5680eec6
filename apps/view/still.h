// Stills that match hr::render pixel for pixel: the scene drawn at k times the size without
// multisampling (k x k samples per pixel, at the very positions of hr::render's grid), each sample's
// radiance recovered by inverting the tone curve of its 8-bit value, the k x k samples averaged in
// linear radiance and tone-mapped again. Averaging tone-mapped colours instead (multisampling) darkens
// bright silhouettes: a reflector's edge against the dark would show a third of its brightness.
#pragma once
#include <vtkRenderer.h>

#include <vector>

namespace view {

/// k x k samples per pixel from an image of (k w) x (k h) RGB8 tone-mapped values, rows from the top.
std::vector<unsigned char> downsampleStill(const std::vector<unsigned char>& samples, int w, int h, int k, double exposure);

/// Draws the renderer (which must be in no window) in an offscreen window of k times the size and
/// returns the w x h still.
std::vector<unsigned char> renderStill(vtkRenderer* r, int w, int h, int k, double exposure);

}  // namespace view
