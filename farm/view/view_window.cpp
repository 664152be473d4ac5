#include "farm/view/view_window.h"

#include <QBuffer>
#include <QCloseEvent>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QKeySequence>
#include <QLabel>
#include <QListWidget>
#include <QMouseEvent>
#include <QPainter>
#include <QProgressBar>
#include <QPushButton>
#include <QShortcut>
#include <QSlider>
#include <QTimer>
#include <QVBoxLayout>
#include <QWheelEvent>
#include <cmath>
#include <cstdio>
#include <sys/mman.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "farm/view/farm_view.h"
#include "farm/view/orbit_camera.h"
#include "farm/process/interrupt.h"
#include "farm/commands/preview_spawn.h"

namespace rf::view {

/// The picture, drawn 1:1 at the target size (a low-resolution moving frame is scaled up with
/// nearest-neighbour), and the mouse input on it.
class ImageView : public QWidget {
public:
    ImageView(ViewWindow* w, int width, int height) : QWidget(w), window_(w) {
        setFixedSize(width, height);
        setFocusPolicy(Qt::StrongFocus);
        setAttribute(Qt::WA_OpaquePaintEvent);
    }

protected:
    void paintEvent(QPaintEvent*) override {
        QPainter p(this);
        const QImage& img = window_->picture_;
        if (img.isNull()) {
            p.fillRect(rect(), Qt::black);
            return;
        }
        p.setRenderHint(QPainter::SmoothPixmapTransform, false);
        p.drawImage(rect(), img);
        if (window_->tint_) paintTint(p);
    }
    void mousePressEvent(QMouseEvent* e) override { last_ = e->position(); }
    void mouseMoveEvent(QMouseEvent* e) override {
        const QPointF d = e->position() - last_;
        last_ = e->position();
        const Qt::MouseButtons b = e->buttons();
        const Qt::MouseButton button = (b & Qt::LeftButton) ? Qt::LeftButton : (b & Qt::MiddleButton) ? Qt::MiddleButton : Qt::NoButton;
        if (button != Qt::NoButton) window_->dragBy(button, e->modifiers(), d.x(), d.y());
    }
    void wheelEvent(QWheelEvent* e) override { window_->wheelBy(e->angleDelta().y() / 120.0); }

private:
    void paintTint(QPainter& p) {
        // One hue per rank, half transparent, over each 32×32 tile of the target size.
        const int t = kTintTile, cols = (width() + t - 1) / t;
        const std::vector<uint8_t>& ranks = window_->tileRanks_;
        for (size_t i = 0; i < ranks.size(); ++i) {
            const QColor c = QColor::fromHsv((ranks[i] * 97) % 360, 255, 255, 90);
            p.fillRect(QRect(int(i % cols) * t, int(i / cols) * t, t, t), c);
        }
    }

    ViewWindow* window_;
    QPointF last_;
};

ViewWindow::ViewWindow(LoadedScene loaded, anim::Timeline timeline, RenderSettings settings, ViewOptions options)
    : scene_(std::move(loaded.scene)), source_(std::move(loaded.timeline)), timeline_(timeline), sceneTimeline_(std::move(timeline)), settings_(settings), options_(std::move(options)),
      start_(Clock::now()) {
    film_ = filmOf(timeline_);
    bounds_ = scene_.geometry.bounds();
    frame_ = std::clamp(options_.startFrame, 0, film_.frames - 1);
    // The free camera starts where the timeline puts it at the first frame shown.
    Scene posed = scene_;
    timeline_.applyFrame(posed, frame_);
    camera_ = followCamera_ = posed.camera;
    followFrame_ = frame_;
    buildUi();
    addShortcuts();
    startRenderer();
    setWindowTitle(QString::fromStdString("rayfarm view - " + options_.scenePath));
}

ViewWindow::~ViewWindow() = default;

void ViewWindow::startRenderer() {
    // Pictures and the session's end come on the farm's thread; the window takes them on its
    // own thread, from its event queue.
    Publish publish = [this](ViewFrame&& f) {
        auto shared = std::make_shared<ViewFrame>(std::move(f));
        QMetaObject::invokeMethod(this, [this, shared] { showFrame(std::move(*shared)); }, Qt::QueuedConnection);
    };
    auto onEnd = [this](const SessionEnd& end) {
        if (end.signalled) {
            // mpirun's SIGTERM: SIGKILL follows within a second, the window thread may be busy.
            std::fprintf(stderr, "rayfarm: error: view: %s\n", end.error.c_str());
            std::fflush(stderr);
        }
        QMetaObject::invokeMethod(this, [this, end] { sessionEnded(end); }, Qt::QueuedConnection);
    };
    renderer_ = std::make_unique<FarmView>(options_.transport, LoadedScene{scene_, source_}, settings_, options_.threads, publish, onEnd,
                                           options_.bounceSlot);
    dirty_ = true;
    pump();
    sendRest();
}

void ViewWindow::sessionEnded(const SessionEnd& end) {
    reportedError_ = true;
    playTimer_->stop();
    if (playing_) togglePlay();
    if (end.signalled) {
        // Under mpirun a SIGTERM means mpirun is ending the job, usually because a rank died (it
        // does not wait for rank 0 to notice), and SIGKILL follows within a second: the line
        // naming the dead rank is out (on the farm's thread). The report must outlive the job:
        // a window of its own process shows it over the last picture. Then leave before the
        // kill, as MPI_Finalize would wait for the dead rank.
        if (end.lostRank > 0) openStoppedReport(end.error);
        std::_Exit(end.lostRank > 0 ? 1 : 130);
    }
    // A rank died or failed: say so where it stays in sight, render no more.
    std::fprintf(stderr, "rayfarm: error: view: %s; the session stops (close the window)\n", end.error.c_str());
    showStopped(end.error);
    updateStatus();
}

void ViewWindow::openStoppedReport(const std::string& why) {
    // The picture travels in an anonymous file as the report's fd 3: nothing is left on disk.
    QByteArray png;
    QBuffer buffer(&png);
    buffer.open(QIODevice::WriteOnly);
    picture_.save(&buffer, "PNG");
    const int fd = memfd_create("rayfarm-view-stopped", 0);
    if (fd < 0 || ::write(fd, png.constData(), size_t(png.size())) != png.size()) {
        std::fprintf(stderr, "rayfarm: note: view: cannot keep the last picture for the report window\n");
    }
    const std::string err = farm::spawnView({"--stopped", why, "--picture", fd >= 0 ? "/dev/fd/3" : ""}, fd);
    if (!err.empty()) std::fprintf(stderr, "rayfarm: note: view: cannot open the report window (%s)\n", err.c_str());
    std::fflush(stderr);
}

void ViewWindow::buildUi() {
    auto* grid = new QGridLayout(this);
    grid->setContentsMargins(0, 0, 0, 0);
    grid->setSpacing(0);
    image_ = new ImageView(this, settings_.width, settings_.height);
    grid->addWidget(image_, 0, 0, Qt::AlignLeft | Qt::AlignTop);
    // Across the window's top, over the picture, hidden until the farm stops for good.
    banner_ = new QLabel(this);
    banner_->setObjectName("stopped");
    banner_->setWordWrap(true);
    banner_->setStyleSheet("QLabel { background: #c00000; color: white; padding: 4px; font-weight: bold; }");
    banner_->hide();
    grid->addWidget(banner_, 0, 0, 1, 2, Qt::AlignTop);
    grid->addLayout(buildSide(), 0, 1);
    grid->addLayout(buildTimelineBar(), 1, 0, 1, 2);
    status_ = new QLabel;
    status_->setContentsMargins(6, 2, 6, 4);
    grid->addWidget(status_, 2, 0, 1, 2);

    restTimer_ = new QTimer(this);
    restTimer_->setSingleShot(true);
    connect(restTimer_, &QTimer::timeout, this, [this] { sendRest(); });
    playTimer_ = new QTimer(this);
    playTimer_->setInterval(std::max(1, int(std::lround(1000.0 / film_.fps))));
    connect(playTimer_, &QTimer::timeout, this, [this] { setFrame((frame_ + 1) % film_.frames, false); });
    image_->setFocus();
}

QVBoxLayout* ViewWindow::buildSide() {
    auto* side = new QVBoxLayout;
    side->setContentsMargins(6, 6, 6, 6);
    side->addWidget(new QLabel("Camera keys (K adds)"));
    keyList_ = new QListWidget;
    keyList_->setFocusPolicy(Qt::NoFocus);
    side->addWidget(keyList_);
    auto* jump = new QPushButton("Jump");
    auto* del = new QPushButton("Delete");
    for (QPushButton* b : {jump, del}) b->setFocusPolicy(Qt::NoFocus);
    auto* keyButtons = new QHBoxLayout;
    keyButtons->addWidget(jump);
    keyButtons->addWidget(del);
    side->addLayout(keyButtons);
    connect(jump, &QPushButton::clicked, this, [this] { jumpToKey(keyList_->currentRow()); });
    connect(del, &QPushButton::clicked, this, [this] { deleteKey(keyList_->currentRow()); });
    connect(keyList_, &QListWidget::itemDoubleClicked, this, [this] { jumpToKey(keyList_->currentRow()); });
    renderButton_ = new QPushButton("Render MP4 (Ctrl+R)");
    renderButton_->setFocusPolicy(Qt::NoFocus);
    renderBar_ = new QProgressBar;
    renderBar_->setRange(0, 1);
    renderBar_->setValue(0);
    side->addWidget(renderButton_);
    side->addWidget(renderBar_);
    connect(renderButton_, &QPushButton::clicked, this, [this] { renderFilm(); });
    return side;
}

QHBoxLayout* ViewWindow::buildTimelineBar() {
    auto* bar = new QHBoxLayout;
    bar->setContentsMargins(6, 4, 6, 0);
    play_ = new QPushButton("Play");
    play_->setFocusPolicy(Qt::NoFocus);
    slider_ = new QSlider(Qt::Horizontal);
    slider_->setRange(0, film_.frames - 1);
    slider_->setValue(frame_);
    slider_->setFocusPolicy(Qt::NoFocus);
    timeLabel_ = new QLabel;
    bar->addWidget(play_);
    bar->addWidget(slider_, 1);
    bar->addWidget(timeLabel_);
    connect(play_, &QPushButton::clicked, this, [this] { togglePlay(); });
    connect(slider_, &QSlider::valueChanged, this, [this](int v) {
        if (v != frame_) setFrame(v, true);
    });
    return bar;
}

void ViewWindow::showStopped(const std::string& why) {
    // It stays until the window closes: the status line below changes with every frame.
    banner_->setText(QString::fromStdString("Rendering stopped: " + why + "\nClose the window to end the session."));
    banner_->show();
    banner_->raise();
    setWindowTitle(QString::fromStdString("rayfarm view - " + options_.scenePath + " - stopped: " + why));
}

void ViewWindow::addShortcuts() {
    auto add = [this](const QKeySequence& k, auto fn) {
        auto* s = new QShortcut(k, this);
        connect(s, &QShortcut::activated, this, fn);
    };
    add(QKeySequence(Qt::Key_F), [this] {
        takeShownCamera();
        camera_ = frameBox(camera_, bounds_, double(settings_.width) / settings_.height);
        follow_ = false;
        cameraEdited();
    });
    add(QKeySequence(Qt::Key_R), [this] { follow_ = true; cameraEdited(); });
    add(QKeySequence(Qt::Key_T), [this] { tint_ = !tint_; image_->update(); updateStatus(); });
    add(QKeySequence(Qt::Key_K), [this] { addKey(); });
    add(QKeySequence(Qt::Key_Space), [this] { togglePlay(); });
    add(QKeySequence(Qt::Key_Right), [this] { setFrame(std::min(frame_ + 1, film_.frames - 1), true); });
    add(QKeySequence(Qt::Key_Left), [this] { setFrame(std::max(frame_ - 1, 0), true); });
    add(QKeySequence(Qt::Key_Home), [this] { setFrame(0, true); });
    add(QKeySequence(Qt::Key_End), [this] { setFrame(film_.frames - 1, true); });
    add(QKeySequence(Qt::Key_Delete), [this] { deleteKey(keyList_->currentRow()); });
    add(QKeySequence(QKeySequence::Save), [this] { save(); });
    add(QKeySequence(Qt::CTRL | Qt::Key_R), [this] { renderFilm(); });
    add(QKeySequence(Qt::CTRL | Qt::Key_Q), [this] { close(); });
}

void ViewWindow::togglePlay() {
    playing_ = !playing_;
    play_->setText(playing_ ? "Pause" : "Play");
    if (playing_) {
        playTimer_->start();
    } else {
        playTimer_->stop();
        sendRest();
    }
}

void ViewWindow::takeShownCamera() {
    if (!follow_) return;
    if (followFrame_ != frame_) {
        Scene posed = scene_;
        timeline_.applyFrame(posed, frame_);
        followCamera_ = posed.camera;
        followFrame_ = frame_;
    }
    camera_ = followCamera_;
}

void ViewWindow::dragBy(Qt::MouseButton button, Qt::KeyboardModifiers mods, double dx, double dy) {
    takeShownCamera();
    if (button == Qt::MiddleButton || (mods & Qt::ShiftModifier)) camera_ = pan(camera_, dx, dy, settings_.height);
    else camera_ = orbit(camera_, dx, dy);
    follow_ = false;
    cameraEdited();
}

void ViewWindow::wheelBy(double steps) {
    takeShownCamera();
    camera_ = zoom(camera_, steps);
    follow_ = false;
    cameraEdited();
}

void ViewWindow::cameraEdited() {
    if (!pendingInput_) pendingInput_ = Clock::now();
    dirty_ = true;
    restTimer_->start(150);
    pump();
}

void ViewWindow::setFrame(int frame, bool fromInput) {
    frame_ = frame;
    if (slider_->value() != frame) slider_->setValue(frame);
    if (fromInput && !pendingInput_) pendingInput_ = Clock::now();
    dirty_ = true;
    if (!playing_) restTimer_->start(150);
    pump();
}

void ViewWindow::pump() {
    // One moving frame in flight at a time: newer input waits for it and then goes out as one
    // request, rather than cancelling every frame before it reaches the screen.
    if (!dirty_ || movingInFlight_ != 0 || filming_ || !renderer_ || reportedError_) return;
    ViewRequest r{camera_, frame_, true, follow_, pendingInput_};
    lastEpoch_ = movingInFlight_ = renderer_->request(r);
    pendingInput_.reset();
    dirty_ = false;
}

void ViewWindow::sendRest() {
    if (playing_ || filming_ || !renderer_ || reportedError_) return;
    if (dirty_ || movingInFlight_ != 0) {  // still moving: rest after the last moving frame
        restTimer_->start(50);
        return;
    }
    lastEpoch_ = renderer_->request(ViewRequest{camera_, frame_, false, follow_, std::nullopt});
}

void ViewWindow::showFrame(ViewFrame&& f) {
    if (f.epoch != lastEpoch_) return;  // a view the user has left already
    if (f.moving && f.complete) movingInFlight_ = 0;
    picture_ = QImage(f.rgb.data(), f.width, f.height, f.width * 3, QImage::Format_RGB888).copy();
    tileRanks_ = std::move(f.tileRank);
    image_->repaint();  // on screen now, so the latency below is input to display
    if (f.complete) {
        const double now = nowS();
        const double latency = f.input ? std::chrono::duration<double, std::milli>(Clock::now() - *f.input).count() : -1.0;
        stats_.frameShown(now, f.moving, latency, f.width);
        shownSpp_ = f.spp;
        passMs_ = f.passMs;
        ++fpsFrames_;
        if (now - fpsWindowStart_ >= 1.0) {
            fps_ = fpsFrames_ / (now - fpsWindowStart_);
            fpsFrames_ = 0;
            fpsWindowStart_ = now;
        }
        updateStatus();
    }
    pump();
}

void ViewWindow::updateStatus() {
    const std::string err = renderer_ ? renderer_->error() : "";
    char buf[512];
    std::snprintf(buf, sizeof buf, "%.1f fps | %.1f ms/frame | %d/%d spp | %s x %d threads | frame %d/%d (%.2f s) | camera: %s%s%s%s",
                  fps_, passMs_, shownSpp_, settings_.spp, ranksText().c_str(), threads(), frame_, film_.frames - 1,
                  timeline_.frameTime(frame_), follow_ ? "timeline" : "free", tint_ ? " | tiles tinted by rank" : "",
                  message_.empty() && err.empty() ? "" : " | ", (err.empty() ? message_ : "render error: " + err).c_str());
    status_->setText(QString::fromUtf8(buf));
    char t[64];
    std::snprintf(t, sizeof t, "%.2f s", timeline_.frameTime(frame_));
    timeLabel_->setText(t);
}

std::string ViewWindow::ranksText() const {
    const int n = renderer_ ? renderer_->ranks() : 1;
    return n == 1 ? "1 rank" : std::to_string(n) + " ranks (" + std::to_string(n - 1) + " rendering)";
}

double ViewWindow::nowS() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

void ViewWindow::closeEvent(QCloseEvent* e) {
    playTimer_->stop();
    const int threads = this->threads(), ranks = renderer_ ? renderer_->ranks() : 1;
    // Cancels the pass in flight (and a film render started here, its frames kept), joins the
    // farm's thread and tells every rank to stop.
    renderer_.reset();
    if (filming_)
        std::fprintf(stderr, "rayfarm: view: render cancelled by closing the window: %d frames kept in %s; Render resumes\n",
                     keptFrames(), renderFramesDir_.c_str());
    if (!options_.statsPath.empty()) {
        try {
            stats_.write(options_.statsPath, settings_.width, settings_.height, ranks, threads);
        } catch (const std::exception& ex) {
            std::fprintf(stderr, "rayfarm: error: %s\n", ex.what());
        }
    }
    e->accept();
}

}  // namespace rf::view
