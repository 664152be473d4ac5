#pragma once
/// One film on every rank: the scene shared, the job decided, then rank 0's farm or a worker's
/// loop.
#include <chrono>
#include <string>
#include <vector>

#include "farm/cli/cli.h"
#include "farm/cluster/render_job.h"
#include "farm/cluster/transport.h"

namespace rf::cli {

/// Where a film stands in a job of several (null: a job of one film).
struct FilmInJob {
    int index = 0, count = 1;
};

/// One film on every rank: the scene shared, the job decided, rank 0's farm or a worker's loop.
/// Returns the exit status (rank 0 may throw instead, as a job of one film has always done).
int renderFilm(farm::MpiTransport& t, const ArgParser& p, const std::vector<std::string>& args, farm::RenderJob job,
               std::chrono::steady_clock::time_point wallStart, const FilmInJob* film);

}  // namespace rf::cli
