#pragma once
/// `rayfarm view --watch DIR` (and `render --preview`, which starts it): a window on the PNG
/// frames a render writes as they complete, with the progress figures (frames, fps, ETA). It
/// only reads the directory, so closing it never touches the render.
#include <QImage>
#include <QWidget>
#include <chrono>
#include <set>
#include <string>

class QLabel;
class QTimer;

namespace rf::view {

class PreviewWindow : public QWidget {
public:
    /// total: frames the render will write (0: unknown).
    PreviewWindow(std::string framesDir, int total);

private:
    void scan();

    std::string dir_;
    int total_;
    std::set<std::string> seen_;
    std::chrono::steady_clock::time_point firstSeen_;
    int seenAtFirst_ = -1;
    QLabel* picture_ = nullptr;
    QLabel* status_ = nullptr;
    QTimer* timer_ = nullptr;
};

/// `rayfarm view --stopped TEXT --picture PNG`: what a view session's window opens as it goes
/// when mpirun ends the whole job (a rank died): the last picture under a red banner saying
/// why, in a process of its own that outlives the job, until the user closes it.
class StoppedWindow : public QWidget {
public:
    StoppedWindow(const std::string& why, const std::string& picturePath);
};

}  // namespace rf::view
