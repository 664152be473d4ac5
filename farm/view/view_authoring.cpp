// The window's authoring side: camera keys (add, list, jump, delete) and saving the scene with
// its keyed timeline.
#include <QCoreApplication>
#include <QListWidget>
#include <QProcess>
#include <QProgressBar>
#include <QPushButton>
#include <QTimer>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "view_window.h"

namespace rf::view {

namespace {
/// The environment for a child rayfarm: without the MPI launcher's variables, so that a child
/// of a rank under mpirun starts as a process of its own, not as another member of the job.
QProcessEnvironment childEnvironment() {
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    for (const QString& k : env.keys())
        if (k.startsWith("OMPI_") || k.startsWith("PMIX_") || k.startsWith("OPAL_")) env.remove(k);
    env.insert("OMPI_ALLOW_RUN_AS_ROOT", "1");
    env.insert("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
    return env;
}
}  // namespace

void ViewWindow::addKey() {
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

void ViewWindow::rebuildTimeline() {
    // The window plays the keys through the same parser and evaluator `render` will use on the
    // saved file, so the path on screen is the path rendered.
    std::string json = scene_.timeline ? scene_.timeline->dump() : std::string();
    if (keys_.empty()) {
        timeline_ = sceneTimeline_;
    } else {
        Scene keyed = scene_;
        keyed.timeline = std::make_shared<const nlohmann::json>(nlohmann::json{{"timeline", keyedTimeline(keys_, scene_, film_)}});
        json = keyed.timeline->dump();
        timeline_ = anim::Timeline::fromScene(keyed);
    }
    renderer_->setTimeline(timeline_, json);
    dirty_ = true;
    pump();
    sendRest();
}

void ViewWindow::save() {
    if (keys_.empty()) {
        message_ = "nothing to save: K adds a camera key first";
    } else {
        try {
            writeSceneFile(options_.savePath, sceneDocument(scene_, settings_, keyedTimeline(keys_, scene_, film_)));
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
    if (renderProc_) {  // the button reads Cancel while a render runs
        cancelRender();
        return;
    }
    // With keys the film is the saved scene's; without, the scene's own film at the window's
    // picture settings.
    std::string scene = options_.scenePath;
    QStringList args;
    if (!keys_.empty()) {
        save();
        if (message_.rfind("saved ", 0) != 0) return;
        scene = options_.savePath;
        renderTotal_ = film_.frames;
    } else {
        const std::string size = std::to_string(settings_.width) + "x" + std::to_string(settings_.height);
        args << "--size" << QString::fromStdString(size) << "--spp" << QString::number(settings_.spp) << "--depth"
             << QString::number(settings_.maxDepth);
        renderTotal_ = sceneTimeline_.frameCount();
    }
    const std::filesystem::path base = std::filesystem::path(options_.savePath).replace_extension();
    renderOutput_ = base.string() + ".mp4";
    renderFramesDir_ = base.string() + ".frames";
    args.prepend(QString::fromStdString(renderFramesDir_));
    args.prepend("--frames-dir");
    args.prepend(QString::fromStdString(renderOutput_));
    args.prepend("-o");
    args.prepend(QString::fromStdString(scene));
    args.prepend("render");
    if (renderResumable_) args << "--resume";  // the frames of the cancelled run are kept
    renderProc_ = new QProcess(this);
    renderProc_->setProcessChannelMode(QProcess::ForwardedChannels);
    renderProc_->setProcessEnvironment(childEnvironment());
    connect(renderProc_, &QProcess::finished, this, [this](int code, QProcess::ExitStatus st) {
        renderEnded(st == QProcess::NormalExit ? code : 1);
    });
    renderCancelled_ = false;
    renderProc_->start(QCoreApplication::applicationFilePath(), args);
    renderButton_->setText("Cancel render (Ctrl+R)");
    renderBar_->setRange(0, std::max(1, renderTotal_));
    renderBar_->setValue(0);
    if (!renderTimer_) {
        renderTimer_ = new QTimer(this);
        connect(renderTimer_, &QTimer::timeout, this, [this] { renderProgress(); });
    }
    renderTimer_->start(250);
    message_ = "rendering " + renderOutput_;
    updateStatus();
}

void ViewWindow::renderProgress() {
    // Frames count as done once their PNG is in the frames directory (render writes each one
    // whole, under a .part name first).
    int done = 0;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(renderFramesDir_, ec))
        if (e.path().extension() == ".png" && e.path().filename().string().rfind("frame_", 0) == 0) ++done;
    renderBar_->setValue(std::min(done, renderBar_->maximum()));
}

void ViewWindow::cancelRender() {
    if (!renderProc_) return;
    // Ctrl-C for render: it closes the video on the frames done and keeps their PNGs.
    renderCancelled_ = true;
    ::kill(static_cast<pid_t>(renderProc_->processId()), SIGINT);
    renderProc_->waitForFinished(5000);
}

void ViewWindow::renderEnded(int status) {
    renderTimer_->stop();
    renderProgress();
    renderProc_->deleteLater();
    renderProc_ = nullptr;
    renderButton_->setText("Render MP4 (Ctrl+R)");
    renderResumable_ = renderCancelled_ || status != 0;
    if (status == 0 && !renderCancelled_) {
        message_ = "rendered " + renderOutput_;
    } else {
        message_ = std::string(renderCancelled_ ? "render cancelled" : "render failed") + ": " +
                   std::to_string(renderBar_->value()) + " frames kept in " + renderFramesDir_ + "; Render resumes";
    }
    std::fprintf(stderr, "rayfarm: view: %s\n", message_.c_str());
    updateStatus();
}

}  // namespace rf::view
