#include "view_worker.h"

#include <atomic>
#include <chrono>
#include <deque>
#include <optional>
#include <thread>

#include <nlohmann/json.hpp>

#include "image.h"
#include "interrupt.h"
#include "film_render.h"
#include "messages.h"
#include "render_engine.h"
#include "render_job.h"
#include "render.h"
#include "view_messages.h"
#include "worker.h"

namespace rf::view {

namespace {

using Clock = std::chrono::steady_clock;
/// A film worker whose rank 0 is silent this long leaves (runWorker's masterTimeout).
constexpr double kFilmMasterTimeout = 20.0;

struct WorkerState {
    farm::Transport& t;
    const Scene pristine;
    Scene scene;
    anim::Timeline timeline;
    RenderSettings settings;
    int threads;
    int appliedFrame = -1;
    std::deque<ViewWork> queue;
    uint64_t newest = 0;
    bool stop = false;
    bool signalled = false;  ///< SIGTERM/SIGINT: stopped without rank 0's word
    std::optional<std::string> film;  ///< kTagFilm's payload, to serve before anything else
    Clock::time_point lastBeat = Clock::now();

    /// Takes every waiting message; true if one of them makes `epoch` stale.
    bool drain(uint64_t epoch) {
        farm::Message m;
        while (!film && t.poll(m)) {  // after kTagFilm the film's own messages follow: leave them
            if (m.tag == farm::kTagStop) {
                stop = true;
            } else if (m.tag == farm::kTagFilm) {
                film = std::move(m.bytes);
                queue.clear();  // the window asks for no view while the film renders
            } else if (m.tag == farm::kTagViewWork) {
                const ViewWork w = decodeViewWork(m.bytes);
                if (w.epoch > newest) {
                    newest = w.epoch;
                    std::erase_if(queue, [&](const ViewWork& q) { return q.epoch < newest; });
                }
                queue.push_back(w);
            } else if (m.tag == farm::kTagViewTimeline) {
                Scene keyed = pristine;
                keyed.timeline = m.bytes.empty() ? nullptr : std::make_shared<const nlohmann::json>(nlohmann::json::parse(m.bytes));
                timeline = anim::Timeline::fromScene(keyed);
                scene = pristine;  // a new timeline poses the scene as loaded, not as the old one left it
                appliedFrame = -1;
            }
        }
        beat();
        return stop || film || newest > epoch;
    }

    void beat() {
        if (farm::interruptSignal()) {
            // mpirun ends the job (a rank died, or Ctrl-C): say we live, so rank 0 can tell
            // which rank did not, and render nothing more. SIGKILL follows within a second.
            t.send(0, farm::kTagHeartbeat, farm::encodeHeartbeat({appliedFrame, 1}));
            t.flush(0.5);
            stop = signalled = true;
            return;
        }
        if (Clock::now() - lastBeat < std::chrono::duration<double>(farm::kHeartbeatSeconds)) return;
        t.send(0, farm::kTagHeartbeat, farm::encodeHeartbeat({appliedFrame, 0}));
        lastBeat = Clock::now();
    }

    /// Renders w's rectangle; false when newer work cancelled it. Sets camera to the camera
    /// rendered (the timeline's when following it), which the window's drags start from.
    bool render(const ViewWork& w, std::vector<uint8_t>& rgb, Camera& camera) {
        if (w.frame != appliedFrame) {
            timeline.applyFrame(scene, w.frame);
            appliedFrame = w.frame;
        }
        const Camera cam = w.followTimeline ? scene.camera : w.camera;
        camera = cam;
        RenderSettings s = settings;
        s.spp = w.spp;
        s.width = w.width;
        s.height = w.height;
        Image img(w.rect.width(), w.rect.height());
        std::vector<TileRect> subs = makeTiles(w.rect.width(), w.rect.height(), 16);
        std::atomic<bool> cancelled{false};
        parallelFor(static_cast<int>(subs.size()), threads, [&](int i, int thread) {
            // The calling thread is worker 0 of the pool: it alone talks MPI, between sub-tiles.
            if (thread == 0 && drain(w.epoch)) cancelled = true;
            if (cancelled) return;
            TileRect r = subs[size_t(i)];
            r.x0 += w.rect.x0, r.x1 += w.rect.x0, r.y0 += w.rect.y0, r.y1 += w.rect.y0;
            std::vector<float> buf(size_t(r.pixels()) * 3);
            RayStats rays;
            renderTile(scene, cam, r, s, w.frame, buf.data(), rays);
            img.setTile(r.x0 - w.rect.x0, r.y0 - w.rect.y0, r.width(), r.height(), buf.data());
        });
        if (cancelled || drain(w.epoch)) return false;
        rgb = toRgb8(img, s);
        return true;
    }
};

/// Serves runFarm's work items for the film with the farm's own worker loop, over the scene as
/// loaded with the window's timeline; returns runWorker's status (0: rank 0 said stop).
int serveFilm(WorkerState& st) {
    std::string workerJob, timelineJson;
    decodeFilmStart(*st.film, workerJob, timelineJson);
    st.film.reset();
    Scene keyed = st.pristine;
    keyed.timeline = timelineJson.empty() ? nullptr : std::make_shared<const nlohmann::json>(nlohmann::json::parse(timelineJson));
    anim::Timeline timeline = anim::Timeline::fromScene(keyed);
    farm::RenderEngine engine(std::move(keyed), timeline, farm::decodeWorkerJob(workerJob), st.threads);
    return farm::runWorker(st.t, engine, kFilmMasterTimeout);
}

}  // namespace

int runViewWorker(farm::Transport& t, Scene scene, RenderSettings settings, int threads) {
    farm::installInterruptHandlers();
    WorkerState st{t, scene, scene, anim::Timeline::fromScene(scene), settings, std::max(1, threads)};
    try {
        while (!st.stop) {
            st.drain(0);
            if (st.stop) break;
            if (st.film) {
                if (const int code = serveFilm(st); code != 0) return code;
                continue;
            }
            if (st.queue.empty()) {
                std::this_thread::sleep_for(std::chrono::microseconds(300));
                continue;
            }
            const ViewWork w = st.queue.front();
            st.queue.pop_front();
            if (w.epoch < st.newest) continue;
            ViewTile tile{w, {}};
            if (st.render(w, tile.rgb, tile.work.camera)) t.send(0, farm::kTagViewTile, encodeViewTile(tile));
        }
        t.flush(1.0);
        return st.signalled ? 130 : 0;
    } catch (const farm::TransportError&) {
        return 1;  // rank 0 is gone; mpirun reports it
    } catch (const std::exception& e) {
        try {
            t.send(0, farm::kTagError, e.what());
            t.flush(2.0);
        } catch (...) {
        }
        return 1;
    }
}

}  // namespace rf::view
