// Render windows and frame read-back (see window.h).
#include "window.h"

#include <X11/Xlib.h>
#include <vtkUnsignedCharArray.h>

#include <cstdlib>
#include <string>

namespace view {

void requireDisplay() {
  const char* name = std::getenv("DISPLAY");
  if (!name || !*name)
    throw EnvironmentError("no X display (DISPLAY is not set): VTK draws through X; on a machine without a screen run "
                           "the command under a virtual one: xvfb-run -a glossyhr view ...");
  Display* d = XOpenDisplay(name);
  if (!d)
    throw EnvironmentError(std::string("cannot open the X display \"") + name +
                           "\": is an X server running? Without a screen: xvfb-run -a glossyhr view ...");
  XCloseDisplay(d);
}

vtkSmartPointer<vtkRenderWindow> makeWindow(int w, int h, bool offscreen) {
  auto win = vtkSmartPointer<vtkRenderWindow>::New();
  win->SetOffScreenRendering(offscreen ? 1 : 0);
  win->SetSize(w, h);
  // Multisampling smooths silhouettes as hr::render's 3 x 3 samples per pixel do; inside a triangle
  // the shader still runs once per pixel, at its centre, so smooth shading is not blurred.
  win->SetMultiSamples(8);
  win->SetWindowName("glossyhr view");
  return win;
}

std::vector<unsigned char> grabFrame(vtkRenderWindow* win) {
  const int* size = win->GetSize();
  const int w = size[0], h = size[1];
  auto px = vtkSmartPointer<vtkUnsignedCharArray>::New();
  win->GetPixelData(0, 0, w - 1, h - 1, 0, px, 0);
  std::vector<unsigned char> rgb(std::size_t(w) * h * 3);
  const unsigned char* src = px->GetPointer(0);
  for (int y = 0; y < h; ++y)  // OpenGL's rows start at the bottom
    std::copy(src + std::size_t(h - 1 - y) * w * 3, src + std::size_t(h - y) * w * 3, rgb.begin() + std::ptrdiff_t(y) * w * 3);
  return rgb;
}

}  // namespace view
