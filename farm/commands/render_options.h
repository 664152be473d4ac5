#pragma once
/// render's command line: its options, its help text, and the job they describe before the
/// scene is read.
#include <string>
#include <vector>

#include "farm/cli/cli.h"
#include "farm/cluster/render_job.h"

namespace rf::cli {

/// Declares render's options on p.
void declareRenderOptions(ArgParser& p);
extern const char* kRenderHelp;

/// The options that do not need the scene (paths, mode, encoder), for one scene; name: the
/// film's name, put in place of {name} in the paths; throws UsageError.
farm::RenderJob jobFromOptions(const ArgParser& p, const std::string& scene, const std::string& name);
/// One job per scene on the command line (several: a job of several films, whose paths must
/// hold {name}); throws UsageError.
std::vector<farm::RenderJob> jobsFromOptions(const ArgParser& p);
/// A film's name: its scene file's name without the extension.
std::string filmName(const std::string& scenePath);
/// What one of render's options does to the kept frames, for --resume. An option that changes a
/// pixel of a frame, or which picture a frame index shows, reaches RenderJob::identity() under
/// `identityKeys`; one that does not says why. render_identity_test requires every declared
/// option here, and each of the first kind to change the identity.
struct OptionRole {
    const char* option;
    const char* identityKeys;  ///< the identity's keys its value reaches ("width height"); nullptr: no pixel changes
    const char* why;           ///< how its value gets there, or why it changes no pixel
};
const std::vector<OptionRole>& renderOptionRoles();

/// Parses "A:B", "A:", ":B" or "A" against a timeline of n frames (inclusive, 0-based).
void parseFrameRange(const std::string& text, int n, int& first, int& last);

}  // namespace rf::cli
