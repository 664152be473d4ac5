#pragma once
/// A job of several films on the same ranks, one after another.
#include <string>
#include <vector>

#include "farm/cli/cli.h"
#include "farm/cluster/render_job.h"
#include "farm/cluster/transport.h"

namespace rf::cli {

/// Several films as one job on the same ranks, one after another: each scene is shared once
/// with every rank, each film has its own outputs, locks, frames directory and resume. A film
/// that fails (a broken model, an output that cannot be written, a worker's error) is named and
/// the job goes on with the next; a signal or a lost rank ends the job as it ends one film.
int renderJobOfFilms(farm::MpiTransport& t, const ArgParser& p, const std::vector<std::string>& args,
                     const std::vector<farm::RenderJob>& jobs);

}  // namespace rf::cli
