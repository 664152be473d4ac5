#include "farm/view/preview_window.h"

#include <QLabel>
#include <QKeySequence>
#include <QPixmap>
#include <QShortcut>
#include <QTimer>
#include <QVBoxLayout>
#include <cstdio>
#include <filesystem>

namespace rf::view {

PreviewWindow::PreviewWindow(std::string framesDir, int total) : dir_(std::move(framesDir)), total_(total) {
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(0, 0, 0, 0);
    picture_ = new QLabel("waiting for the first frame …");
    picture_->setAlignment(Qt::AlignLeft | Qt::AlignTop);
    status_ = new QLabel;
    status_->setContentsMargins(6, 2, 6, 4);
    layout->addWidget(picture_, 1);
    layout->addWidget(status_);
    setWindowTitle(QString::fromStdString("rayfarm preview - " + dir_));
    timer_ = new QTimer(this);
    connect(timer_, &QTimer::timeout, this, [this] { scan(); });
    timer_->start(200);
    auto* quit = new QShortcut(QKeySequence(Qt::CTRL | Qt::Key_Q), this);
    connect(quit, &QShortcut::activated, this, [this] { close(); });
    scan();
}

void PreviewWindow::scan() {
    // A frame counts once its PNG has its final name (render writes frame_N.png.part first).
    std::string newest;
    int count = 0;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(dir_, ec)) {
        const std::string name = e.path().filename().string();
        if (name.rfind("frame_", 0) != 0 || e.path().extension() != ".png") continue;
        ++count;
        if (seen_.insert(name).second && name > newest) newest = name;
    }
    const auto now = std::chrono::steady_clock::now();
    if (seenAtFirst_ < 0 && count > 0) {
        seenAtFirst_ = count;
        firstSeen_ = now;
    }
    if (!newest.empty()) {
        const QImage img(QString::fromStdString((std::filesystem::path(dir_) / newest).string()));
        if (!img.isNull()) {
            picture_->setPixmap(QPixmap::fromImage(img));
            picture_->setFixedSize(img.size());
        }
    }
    // Frames per second since the preview saw its first frame, and the time left at that rate.
    const double s = std::chrono::duration<double>(now - firstSeen_).count();
    const double fps = seenAtFirst_ >= 0 && s > 0.5 ? (count - seenAtFirst_) / s : 0.0;
    char buf[256];
    if (total_ > 0) {
        const double eta = fps > 0 ? (total_ - count) / fps : -1.0;
        std::snprintf(buf, sizeof buf, "%d/%d frames  %.1f fps  ETA %s ", count, total_, fps,
                      eta < 0 ? "?" : (std::to_string(int(eta + 0.5)) + " s").c_str());
    } else {
        std::snprintf(buf, sizeof buf, "%d frames  %.1f fps ", count, fps);
    }
    status_->setText(QString::fromUtf8(buf) + (count > 0 ? QString::fromStdString("| showing " + *seen_.rbegin()) : QString()));
}

StoppedWindow::StoppedWindow(const std::string& why, const std::string& picturePath) {
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(0, 0, 0, 0);
    layout->setSpacing(0);
    // The same banner as the view window's (ViewWindow::showStopped).
    auto* banner = new QLabel(QString::fromStdString("Rendering stopped: " + why + "\nmpirun ended the session; close this window."));
    banner->setWordWrap(true);
    banner->setStyleSheet("QLabel { background: #c00000; color: white; padding: 4px; font-weight: bold; }");
    layout->addWidget(banner);
    auto* picture = new QLabel;
    const QImage img(QString::fromStdString(picturePath));
    if (!img.isNull()) {
        picture->setPixmap(QPixmap::fromImage(img));
        picture->setFixedSize(img.size());
    }
    layout->addWidget(picture, 1, Qt::AlignLeft | Qt::AlignTop);
    setWindowTitle(QString::fromStdString("rayfarm view - stopped: " + why));
    auto* quit = new QShortcut(QKeySequence(Qt::CTRL | Qt::Key_Q), this);
    connect(quit, &QShortcut::activated, this, [this] { close(); });
}

}  // namespace rf::view
