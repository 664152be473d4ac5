#include "farm/view/farm_view.h"

#include <algorithm>
#include <cstring>

#include <nlohmann/json.hpp>

#include "farm/process/interrupt.h"
#include "engine/util/load_control.h"
#include "farm/cluster/loopback_transport.h"
#include "farm/cluster/master.h"
#include "farm/cluster/messages.h"

namespace rf::view {

namespace {

/// A rank silent this long, busy or idle, is reported lost (heartbeats come every 0.1 s).
constexpr double kSilenceSeconds = 5.0;

/// The 8-bit picture as the window draws it: RGB; a transparent background's straight RGBA
/// is shown over black.
void toRgb(const std::vector<uint8_t>& px, size_t pixels, std::vector<uint8_t>& rgb) {
    if (px.size() == pixels * 3) {
        rgb = px;
        return;
    }
    rgb.resize(pixels * 3);
    for (size_t i = 0; i < pixels; ++i)
        for (int c = 0; c < 3; ++c) rgb[3 * i + c] = uint8_t((px[4 * i + c] * px[4 * i + 3] + 127) / 255);
}

/// "rank 2 stopped answering (silent for 5.0 s) while rendering frame 0, on host vm" from the
/// master's "rank 2 on vm stopped answering (silent for 5.0 s) while rendering frame 0 …".
std::string lostRankLine(int rank, const std::string& master, bool signalled) {
    const std::string who = "rank " + std::to_string(rank), verb = " stopped answering";
    const size_t at = master.find(verb);
    std::string detail = at == std::string::npos ? "" : master.substr(at + verb.size());
    if (signalled) detail = " while mpirun ended the session (it died, and mpirun ends the whole session with it)";
    std::string host;
    if (at != std::string::npos && master.rfind(who + " on ", 0) == 0) host = master.substr(who.size() + 4, at - who.size() - 4);
    return who + verb + detail + (host.empty() ? "" : ", on host " + host);
}

}  // namespace

FarmView::FarmView(farm::Transport* t, LoadedScene loaded, RenderSettings settings, int threads, Publish publish,
                   std::function<void(const SessionEnd&)> onEnd, std::shared_ptr<SceneCacheSlot> bounceSlot)
    : hub_(t ? nullptr : std::make_unique<farm::LoopbackHub>(1)),
      alone_(t ? nullptr : std::make_unique<farm::LoopbackTransport>(*hub_, 0)), t_(t ? *t : *alone_),
      scene_(std::move(loaded.scene)), source_(std::move(loaded.timeline)), settings_(settings),
      bounceSlot_(bounceSlot ? std::move(bounceSlot) : std::make_shared<SceneCacheSlot>()), threads_(threads > 0 ? threads : hardwareThreads()), ranks_(t_.size()),
      publish_(std::move(publish)), onEnd_(std::move(onEnd)) {
    timelineJson_ = sectionsText(source_);
    thread_ = std::thread([this] { farmLoop(); });
}

FarmView::~FarmView() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        closing_ = true;
    }
    sessionCancel_ = true;
    filmCancel_ = true;
    cv_.notify_all();
    thread_.join();
    stopRanks();
}

void FarmView::stopRanks() {
    try {
        farm::tellWorkersToStop(t_, 1.0);
    } catch (const farm::TransportError&) {
        // A rank is gone already; mpirun ends the rest.
    }
}

uint64_t FarmView::request(const ViewRequest& r) {
    uint64_t id;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        id = ++nextId_;
        current_ = r;
        currentId_ = id;
        currentAnswered_ = false;
    }
    inbox_.post(orderFor(r, id));
    return id;
}

farm::ViewOrder FarmView::orderFor(const ViewRequest& r, uint64_t id) const {
    farm::ViewOrder o;
    o.id = id;
    o.frame = r.frame;
    o.followTimeline = r.followTimeline;
    o.camera = r.camera;
    if (r.moving) {
        const int s = scale_;
        o.passes.push_back({1, std::max(1, (settings_.width + s - 1) / s), std::max(1, (settings_.height + s - 1) / s)});
    } else {
        for (int spp : refinementSpp(settings_.spp)) o.passes.push_back({spp, settings_.width, settings_.height});
    }
    return o;
}

void FarmView::setTimeline(const std::string& timelineJson) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        timelineJson_ = timelineJson;
        timelineChanged_ = true;
    }
    sessionCancel_ = true;  // the session starts again over the new timeline
    cv_.notify_all();
}

void FarmView::startFilm(FilmRequest r, FilmCallbacks cb) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        film_.emplace(std::move(r), std::move(cb));
    }
    filmCancel_ = false;
    sessionCancel_ = true;
    cv_.notify_all();
}

std::string FarmView::error() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return error_;
}

void FarmView::farmLoop() {
    for (;;) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (closing_ || ended_) return;
        }
        sendTimeline();
        bool film;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            film = film_.has_value();
        }
        if (film) runFilm();
        else runSession();
    }
}

void FarmView::sendTimeline() {
    std::string json;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!timelineChanged_) return;
        timelineChanged_ = false;
        json = timelineJson_;
    }
    // Ranks 1…N−1 pose the scene as loaded with it (runViewWorker); rank 0 builds its engine
    // for the next session or film from the same JSON.
    for (int r = 1; r < t_.size(); ++r) t_.send(r, farm::kTagViewTimeline, json);
}

void FarmView::runSession() {
    farm::SharedScene shared;
    shared.scene = scene_;
    shared.bounceSlot = bounceSlot_;  // a new session (after a key, after a film) finds the cache built
    {
        std::lock_guard<std::mutex> lock(mutex_);
        shared.timeline = withSections(source_, timelineJson_);
        sessionCancel_ = closing_ || film_.has_value() || timelineChanged_;
        // The last request, if it is not answered yet, is asked again of the new session (an
        // answered one again would count its input's latency twice).
        if (current_ && !currentAnswered_) inbox_.post(orderFor(*current_, currentId_));
    }
    farm::RenderJob job;
    job.settings = settings_;
    job.workerTimeout = kSilenceSeconds;
    farm::FarmOptions opts;
    opts.views = &inbox_;
    opts.keepWorkers = true;
    opts.threads = threads_;
    opts.cancel = &sessionCancel_;
    opts.quiet = true;
    opts.onFrame = [this](const farm::FarmProgress& p) { onPicture(p); };
    try {
        const farm::FarmOutcome o = farm::runFarm(t_, job, shared, {}, opts);
        if (o.end != farm::FarmEnd::Cancelled) sessionEnded(o);
    } catch (const std::exception& e) {
        farm::FarmOutcome o;
        o.end = farm::FarmEnd::WorkerLost;
        o.error = e.what();
        sessionEnded(o);
    }
}

void FarmView::sessionEnded(const farm::FarmOutcome& o) {
    SessionEnd end;
    end.signalled = o.signal != 0 || (o.end == farm::FarmEnd::WorkerLost && farm::interruptSignal());
    end.lostRank = o.lostRank;
    if (o.lostRank > 0)
        end.error = lostRankLine(o.lostRank, o.error, end.signalled);
    else if (o.end == farm::FarmEnd::Interrupted)
        end.error = "interrupted: mpirun ended the session";
    else
        end.error = o.error;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        error_ = end.error;
        ended_ = true;
    }
    if (onEnd_) onEnd_(end);
}

void FarmView::runFilm() {
    std::optional<std::pair<FilmRequest, FilmCallbacks>> film;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        film = std::move(film_);
        film_.reset();
        timelineJson_ = film->first.timelineJson;
    }
    film->first.bounceSlot = bounceSlot_;
    for (int r = 1; r < t_.size(); ++r) t_.send(r, farm::kTagViewTimeline, film->first.timelineJson);
    FilmEnd end;
    try {
        end = renderFilm(t_, film->first, film->second, filmCancel_);
    } catch (const std::exception& e) {
        end.kind = FilmEnd::Failed;
        end.message = e.what();
    } catch (const LoadCancelled&) {
        // A signal reached the film's load (it reads the scene's files for the manifest): on
        // this thread, not out of it; the signal itself ends the window.
        end.kind = FilmEnd::Failed;
        end.message = "interrupted while loading the scene";
    }
    if (end.kind == FilmEnd::RankLost) {
        // The lost rank cannot be told to stop: no more views; the window says why.
        std::lock_guard<std::mutex> lock(mutex_);
        error_ = end.message;
        ended_ = true;
    }
    if (film->second.onEnd) film->second.onEnd(end);
}

void FarmView::onPicture(const farm::FarmProgress& p) {
    const farm::ViewPicture& pic = *p.view;
    std::optional<ViewRequest> req;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (pic.id == currentId_) req = current_;
        if (pic.id == currentId_ && pic.complete && pic.pass + 1 == pic.passes) currentAnswered_ = true;
    }
    if (!req) return;  // the window has moved on
    const int w = pic.size.width, h = pic.size.height;
    ViewFrame f;
    f.epoch = pic.id;
    f.width = w;
    f.height = h;
    f.spp = pic.size.spp;
    f.complete = pic.complete;
    f.final = pic.complete && pic.pass + 1 == pic.passes;
    f.moving = req->moving;
    f.passMs = pic.ms;
    f.camera = req->camera;
    f.frame = req->frame;
    f.input = req->input;
    std::vector<uint8_t> rgb;
    toRgb(*p.rgb, size_t(w) * h, rgb);
    if (pic.complete) {
        shown_ = rgb;
        shownW_ = w, shownH_ = h;
        if (req->moving) scale_ = movingScale_.next(pic.ms);
        f.rgb = std::move(rgb);
    } else {
        // A slow pass paints its new tiles over the last whole pass of the same size.
        f.rgb = shownW_ == w && shownH_ == h ? shown_ : std::vector<uint8_t>(size_t(w) * h * 3, 0);
        for (const farm::ViewTile& t : *pic.tiles)
            for (int y = t.rect.y0; y < t.rect.y1; ++y)
                std::memcpy(&f.rgb[(size_t(y) * w + t.rect.x0) * 3], &rgb[(size_t(y) * w + t.rect.x0) * 3], size_t(t.rect.width()) * 3);
    }
    // The rank tint: each 32×32 cell of the target size takes the rank of a tile over it.
    const int scale = (settings_.width + w - 1) / w;
    const int cols = (settings_.width + kTintTile - 1) / kTintTile, rows = (settings_.height + kTintTile - 1) / kTintTile;
    f.tileRank.assign(size_t(cols) * rows, 0);
    for (const farm::ViewTile& t : *pic.tiles)
        for (int cy = t.rect.y0 * scale / kTintTile; cy < rows && cy * kTintTile < t.rect.y1 * scale; ++cy)
            for (int cx = t.rect.x0 * scale / kTintTile; cx < cols && cx * kTintTile < t.rect.x1 * scale; ++cx)
                f.tileRank[size_t(cy) * cols + cx] = static_cast<uint8_t>(t.rank);
    publish_(std::move(f));
}

}  // namespace rf::view
