#pragma once
/// --background COLOR|transparent, for still and render: what primary rays that miss show.
#include <string>

#include "engine/scene/background.h"

namespace rf::cli {

/// "transparent", "#RRGGBB" (sRGB, as on a web page) or "R,G,B" (linear, as in a scene file).
/// Throws UsageError naming --background.
BackgroundChoice parseBackground(const std::string& text);

}  // namespace rf::cli
