#pragma once
/// render --preview: starts `rayfarm view --watch FRAMES_DIR` beside the render, as a process of
/// its own session, so the window shows frames as they complete and closing it (or the render
/// ending) leaves the other alone.
#include <string>

namespace rf::farm {

/// Starts the preview window on framesDir (total frames expected). Without a display it says
/// so in a note and starts nothing; the render goes on either way.
void startPreview(const std::string& framesDir, int total);

}  // namespace rf::farm
