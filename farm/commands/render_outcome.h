#pragma once
/// How a render ended, in the lines the shell tests and users read: written, interrupted or a
/// worker lost, with the command that resumes it.
#include <string>
#include <vector>

#include "farm/cluster/farm_options.h"
#include "farm/cluster/render_job.h"

namespace rf::cli {

/// The command line that resumes this render (--resume added, --overwrite left out), under
/// the launcher it was started with (ranks: the job's). leaveOut, an output option such as
/// "--stats", is left out with its value: the output that could not be written, which the
/// resume would fail on again.
std::string resumeCommand(const std::vector<std::string>& args, int ranks, const std::string& leaveOut = "");

/// Prints how the run ended (the lines the shell tests and users read); returns the exit status.
int reportOutcome(int ranks, const farm::RenderJob& job, const farm::FarmOutcome& o, const std::vector<std::string>& args);

}  // namespace rf::cli
