// An X display for offscreen rendering. Debian's VTK 9.1 renders through GLX only (it is built without
// EGL and OSMesa: vtkRenderingOpenGLConfigure.h), so even an offscreen render window needs an X server.
// When DISPLAY is set it is used; when it is not, a private Xvfb is started for this process (and
// stopped at exit), so `lodforge compare --render` works on a headless machine with the xvfb package.
// docs/image-compare.md, "Headless".
#pragma once

namespace lodforge::render {

// Makes sure DISPLAY names a display that accepts connections; starts a private Xvfb the first time it
// is needed. Throws Error(io) with what to do when DISPLAY is set but cannot be opened, or when no
// DISPLAY is set and Xvfb cannot be started (not installed, or it fails).
void ensureDisplay();

}  // namespace lodforge::render
