// The render window: a check that an X display answers before VTK is asked for a window (Debian's
// VTK 9.1 draws through X only and aborts the process when it cannot connect), windows on screen or
// off it, and frames read back as 8-bit sRGB rows from the top, as the PNG writer takes them.
#pragma once
#include <vtkRenderWindow.h>
#include <vtkSmartPointer.h>

#include <stdexcept>
#include <vector>

namespace view {

/// The machine cannot show or render a window (no X display): exit 1 with the message.
struct EnvironmentError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Throws EnvironmentError, saying what to do (xvfb-run -a), when no X display can be opened.
void requireDisplay();
/// A render window of w x h pixels; offscreen windows are never mapped on the screen.
vtkSmartPointer<vtkRenderWindow> makeWindow(int w, int h, bool offscreen);
/// The last rendered frame, RGB8, rows from the top.
std::vector<unsigned char> grabFrame(vtkRenderWindow* win);

}  // namespace view
