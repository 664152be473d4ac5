#pragma once
/// The window's Render action: the film to an MP4 through the farm's one entry point, runFarm,
/// on the ranks the window already has. Under mpirun, the other ranks leave their view loop for
/// the film (kTagFilm) and come back to it when runFarm tells them to stop; alone, rank 0 is
/// the only rank of a one-rank transport and renders on its own threads.
///
/// runFarm runs on a thread of its own so the window stays live; while it runs, nothing else
/// touches the transport (the window does not step its FarmView), which is what MPI's
/// SERIALIZED thread level asks. Progress and the end come back through callbacks on that
/// thread: the window posts them to its own.
#include <atomic>
#include <functional>
#include <string>
#include <thread>

#include "render_job.h"
#include "scene.h"
#include "settings.h"
#include "transport.h"

namespace rf::view {

struct FilmRequest {
    /// The scene file render would read (the saved scene when there are keys): it names the
    /// frames directory's manifest and the digests that a later --resume compares.
    std::string scenePath;
    Scene scene;               ///< what the window renders, its timeline in place
    std::string timelineJson;  ///< that timeline ({"timeline": …} or ""), for the other ranks
    RenderSettings settings;
    std::string output, framesDir;
    bool resume = false;  ///< keep the frames a cancelled run left in framesDir
    int threads = 1;      ///< rank 0's render threads
};

struct FilmEnd {
    enum Kind { Done, Cancelled, Failed, RankLost } kind = Failed;
    std::string message;  ///< what failed, or which rank was lost
    int framesInVideo = 0;
};

struct FilmCallbacks {
    std::function<void(int done, int total)> onFrame;  ///< after each frame reaches the MP4
    std::function<void(const std::string&)> log;        ///< runFarm's lines ("resume: …")
    std::function<void(const FilmEnd&)> onEnd;          ///< once, after runFarm returned
};

/// The job runFarm renders, as `rayfarm render r.scenePath -o r.output --frames-dir
/// r.framesDir` with the window's picture settings would decide it. Prepares the frames
/// directory (fresh, or checked for a resume); throws cli::UsageError on a mismatch.
farm::RenderJob filmJob(const FilmRequest& r, int ranks, std::string& note);

class FilmRender {
public:
    /// Starts the render. t: the window's MPI transport (other ranks run runViewWorker), or
    /// null to render alone.
    FilmRender(farm::Transport* t, FilmRequest r, FilmCallbacks cb);
    /// Cancels and waits.
    ~FilmRender();
    /// Finished frames stay in the frames directory and in a playable MP4.
    void cancel() { cancel_ = true; }
    bool cancelled() const { return cancel_; }

private:
    void run(FilmRequest r);
    FilmEnd render(farm::Transport& t, FilmRequest& r);

    farm::Transport* t_;
    FilmCallbacks cb_;
    std::atomic<bool> cancel_{false};
    std::thread thread_;
};

/// kTagFilm's payload: the settings every rank renders the film with, and the timeline.
std::string encodeFilmStart(const std::string& workerJob, const std::string& timelineJson);
void decodeFilmStart(const std::string& bytes, std::string& workerJob, std::string& timelineJson);

}  // namespace rf::view
