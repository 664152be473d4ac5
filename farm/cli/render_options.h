#pragma once
/// render's command line: its options, its help text, and the job they describe before the
/// scene is read.
#include <string>

#include "cli.h"
#include "render_job.h"

namespace rf::cli {

/// Declares render's options on p.
void declareRenderOptions(ArgParser& p);
extern const char* kRenderHelp;

/// The options that do not need the scene (paths, mode, encoder); throws UsageError.
farm::RenderJob jobFromOptions(const ArgParser& p);
/// Parses "A:B", "A:", ":B" or "A" against a timeline of n frames (inclusive, 0-based).
void parseFrameRange(const std::string& text, int n, int& first, int& last);

}  // namespace rf::cli
