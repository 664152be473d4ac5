// The window's authoring side: camera keys (add, list, jump, delete) and saving the scene with
// its keyed timeline.
#include <QCoreApplication>
#include <QListWidget>
#include <QProgressBar>
#include <QPushButton>
#include <QTimer>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "farm/process/interrupt.h"
#include "farm/view/view_window.h"

namespace rf::view {


void ViewWindow::addKey() {
    takeShownCamera();  // the key holds the camera on screen
    const double t = timeline_.frameTime(frame_);
    keys_.add(keyFromCamera(camera_, scene_.renderOrigin, t));
    renderResumable_ = false;
    rebuildTimeline();
    refreshKeys();
    char buf[96];
    std::snprintf(buf, sizeof buf, "key added at %.3f s (%zu keys)", t, keys_.keys().size());
    message_ = buf;
    updateStatus();
}

void ViewWindow::jumpToKey(int row) {
    if (row < 0 || size_t(row) >= keys_.keys().size()) return;
    const CameraKey& k = keys_.keys()[size_t(row)];
    const int frame = static_cast<int>(std::lround((k.time - timeline_.frameTime(0)) * film_.fps));
    follow_ = true;  // the keyed timeline puts the camera on the key at its frame
    setFrame(std::clamp(frame, 0, film_.frames - 1), true);
}

void ViewWindow::deleteKey(int row) {
    if (row < 0 || size_t(row) >= keys_.keys().size()) return;
    keys_.remove(row);
    renderResumable_ = false;
    rebuildTimeline();
    refreshKeys();
    message_ = "key deleted (" + std::to_string(keys_.keys().size()) + " keys)";
    updateStatus();
}

void ViewWindow::refreshKeys() {
    keyList_->clear();
    for (const CameraKey& k : keys_.keys()) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "%.3f s  eye (%.3g, %.3g, %.3g)  fov %.1f", k.time, k.eye.x, k.eye.y, k.eye.z, k.fovDeg);
        keyList_->addItem(QString::fromUtf8(buf));
    }
}

TimelineSource ViewWindow::keyedSource(std::string& timelineJson) const {
    if (keys_.empty()) {
        timelineJson = sectionsText(source_);
        return source_;
    }
    const std::string keyed = nlohmann::json{{"timeline", keyedTimeline(keys_, source_, film_)}}.dump();
    timelineJson = keyed;
    return withSections(source_, keyed);  // as the farm's ranks make it from the text
}

void ViewWindow::rebuildTimeline() {
    // The window plays the keys through the same parser and evaluator `render` will use on the
    // saved file, so the path on screen is the path rendered.
    std::string json;
    if (keys_.empty()) {
        timeline_ = sceneTimeline_;
        json = sectionsText(source_);
    } else {
        timeline_ = anim::Timeline::fromScene(scene_, keyedSource(json));
    }
    renderer_->setTimeline(json);
    followFrame_ = -1;  // the camera at a frame may differ now
    dirty_ = true;
    pump();
    sendRest();
}

void ViewWindow::save() {
    if (keys_.empty()) {
        message_ = "nothing to save: K adds a camera key first";
    } else {
        try {
            writeSceneFile(options_.savePath, sceneDocument(scene_, settings_, keyedTimeline(keys_, source_, film_)));
            message_ = "saved " + options_.savePath;
            std::fprintf(stderr, "rayfarm: view: saved %s (%zu camera keys)\n", options_.savePath.c_str(), keys_.keys().size());
        } catch (const std::exception& e) {
            message_ = std::string("save failed: ") + e.what();
            std::fprintf(stderr, "rayfarm: error: %s\n", e.what());
        }
    }
    updateStatus();
}

}  // namespace rf::view

namespace rf::view {

void ViewWindow::renderFilm() {
    if (reportedError_ || !renderer_) return;
    if (filming_) {  // the button reads Cancel while a render runs
        cancelRender();
        return;
    }
    // With keys the film is the saved scene's (so `render` of that file continues it); without,
    // the scene's own film. Either way at the window's picture settings, through runFarm on the
    // ranks this window renders with.
    FilmRequest req;
    req.scenePath = options_.scenePath;
    if (!keys_.empty()) {
        save();
        if (message_.rfind("saved ", 0) != 0) return;
        req.scenePath = options_.savePath;
    }
    req.timeline = keyedSource(req.timelineJson);
    req.scene = scene_;
    req.settings = settings_;
    const std::filesystem::path base = std::filesystem::path(options_.savePath).replace_extension();
    renderOutput_ = req.output = base.string() + ".mp4";
    renderFramesDir_ = req.framesDir = req.output + ".frames";  // as render names it: OUT.frames
    req.resume = renderResumable_;  // the frames of the cancelled run are kept
    req.threads = std::max(1, threads());
    renderTotal_ = timeline_.frameCount();

    FilmCallbacks cb;
    cb.onFrame = [this](int done, int total) {
        QMetaObject::invokeMethod(this, [this, done, total] {
            renderBar_->setRange(0, std::max(1, total));
            renderBar_->setValue(done);
        }, Qt::QueuedConnection);
    };
    cb.log = [](const std::string& line) { std::fprintf(stderr, "rayfarm: %s\n", line.c_str()); };
    cb.onEnd = [this](const FilmEnd& end) {
        QMetaObject::invokeMethod(this, [this, end] { renderEnded(end); }, Qt::QueuedConnection);
    };
    // While the film renders the window asks for no frames: the ranks (and the transport)
    // belong to runFarm until it returns.
    if (playing_) togglePlay();
    renderer_->startFilm(std::move(req), std::move(cb));
    filming_ = true;
    renderButton_->setText("Cancel render (Ctrl+R)");
    renderBar_->setRange(0, std::max(1, renderTotal_));
    renderBar_->setValue(0);
    message_ = "rendering " + renderOutput_;
    std::fprintf(stderr, "rayfarm: view: rendering %s through the farm (%d rank%s)\n", renderOutput_.c_str(),
                 renderer_->ranks(), renderer_->ranks() == 1 ? "" : "s");
    updateStatus();
}

void ViewWindow::cancelRender() {
    // Like Ctrl-C for render: the MP4 is closed on the frames done and their PNGs are kept.
    if (filming_ && renderer_) renderer_->cancelFilm();
}

int ViewWindow::keptFrames() const {
    int kept = 0;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(renderFramesDir_, ec))
        if (e.path().extension() == ".png" && e.path().filename().string().rfind("frame_", 0) == 0) ++kept;
    return kept;
}

void ViewWindow::renderEnded(const FilmEnd& end) {
    if (!renderer_) return;  // the window closed meanwhile
    const bool cancelled = renderer_->filmCancelled();
    filming_ = false;
    renderButton_->setText("Render MP4 (Ctrl+R)");
    renderResumable_ = end.kind != FilmEnd::Done;
    const int kept = keptFrames();
    if (end.kind == FilmEnd::Done) {
        renderBar_->setValue(renderBar_->maximum());
        message_ = "rendered " + renderOutput_;
    } else if (end.kind == FilmEnd::RankLost) {
        // The lost rank cannot be told to stop: the session ends with the window.
        reportedError_ = true;
        message_ = "render stopped: " + end.message;
        std::fprintf(stderr, "rayfarm: error: view: %s; the session stops (close the window)\n", message_.c_str());
        std::fflush(stderr);
        // After mpirun's SIGTERM (it ends the job when a rank dies) SIGKILL follows within a
        // second: leave first, the MP4 is closed and the line is out.
        if (farm::interruptSignal()) std::_Exit(1);
        showStopped(message_);
        updateStatus();
        return;
    } else {
        message_ = std::string(cancelled ? "render cancelled" : "render failed: " + end.message) + ": " +
                   std::to_string(kept) + " frames kept in " + renderFramesDir_ + "; Render resumes";
    }
    std::fprintf(stderr, "rayfarm: view: %s\n", message_.c_str());
    movingInFlight_ = 0;  // a moving frame asked for before the film never came back
    dirty_ = true;
    pump();
    sendRest();
    updateStatus();
}

}  // namespace rf::view
