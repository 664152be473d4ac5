#pragma once
/// render --preview: starts `rayfarm view --watch FRAMES_DIR` beside the render, as a process of
/// its own session, so the window shows frames as they complete and closing it (or the render
/// ending) leaves the other alone.
#include <string>
#include <vector>

namespace rf::farm {

/// Starts the preview window on framesDir (total frames expected). Without a display it says
/// so in a note and starts nothing; the render goes on either way.
void startPreview(const std::string& framesDir, int total);

/// Starts `rayfarm view ARGS…` as a process of its own session, outside any MPI job (the
/// launcher's variables left out) and with /dev/null for its standard streams, so that
/// neither mpirun ending the job nor Ctrl-C on the terminal closes its window. passFd >= 0 is
/// its fd 3. Returns "" or why it could not (no display, no executable, spawn's error).
std::string spawnView(const std::vector<std::string>& args, int passFd = -1);

}  // namespace rf::farm
