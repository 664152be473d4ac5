#pragma once
/// The viewer's window (Qt 6 Widgets): the picture at its rendered size in the top-left corner,
/// the camera keys beside it, the timeline bar and the status line below. Input edits a camera
/// and a frame index; the farm (FarmView, through runFarm) turns them into pictures.
#include <QImage>
#include <QWidget>
#include <memory>
#include <optional>
#include <string>

#include "farm/view/camera_keys.h"
#include "farm/view/film_render.h"
#include "farm/view/farm_view.h"
#include "farm/view/view_stats.h"
#include "engine/scene/scene_cache.h"

class QHBoxLayout;
class QLabel;
class QProgressBar;
class QListWidget;
class QPushButton;
class QSlider;
class QTimer;
class QVBoxLayout;

namespace rf::farm {
class Transport;
}

namespace rf::view {

class ImageView;

/// Everything the window needs from the command line.
struct ViewOptions {
    std::string scenePath;
    std::string savePath;   ///< where Ctrl+S writes the scene with its timeline
    std::string statsPath;  ///< --stats, "" for none
    int threads = 0;
    int startFrame = 0;
    /// Under mpirun: rank 0's transport; the other ranks render (runViewWorker). Null: this
    /// process renders alone.
    farm::Transport* transport = nullptr;
    /// The window's bounce cache (bounce_cache.h): the exposure metering, every view session
    /// and every film share it, as the frames of one render job do.
    std::shared_ptr<SceneCacheSlot> bounceSlot = std::make_shared<SceneCacheSlot>();
};

class ViewWindow : public QWidget {
public:
    /// scene: loaded, posed at no particular frame; settings: the target picture.
    ViewWindow(LoadedScene loaded, anim::Timeline timeline, RenderSettings settings, ViewOptions options);
    ~ViewWindow() override;

    /// True once the rendering stopped on an error (a render failure, a lost rank).
    bool failed() const { return reportedError_; }

    // Input from the picture, in the picture's pixels.
    void dragBy(Qt::MouseButton button, Qt::KeyboardModifiers mods, double dx, double dy);
    void wheelBy(double steps);

protected:
    void closeEvent(class QCloseEvent* e) override;

private:
    void startRenderer();
    /// The farm stopped for good (a lost rank, a failure, mpirun's SIGTERM): say so in the
    /// window, or after a signal leave before mpirun's SIGKILL.
    void sessionEnded(const SessionEnd& end);
    /// After mpirun's SIGTERM: a StoppedWindow in a process of its own (it outlives the job)
    /// with the picture on screen and why the session stopped.
    void openStoppedReport(const std::string& why);
    /// camera_ = the camera the picture shows (the timeline's at the current frame when
    /// following it), before an edit starts from it.
    void takeShownCamera();
    void togglePlay();
    void buildUi();
    QVBoxLayout* buildSide();
    QHBoxLayout* buildTimelineBar();
    /// A lasting red banner over the picture and the window title name what stopped the farm.
    void showStopped(const std::string& why);
    void addShortcuts();
    void cameraEdited();
    void setFrame(int frame, bool fromInput);
    void pump();
    void sendRest();
    void showFrame(ViewFrame&& f);
    void updateStatus();
    void refreshKeys();
    void addKey();
    void jumpToKey(int row);
    void deleteKey(int row);
    void save();
    void rebuildTimeline();
    /// scene_ with the keys' timeline in place (the scene's own without keys), and that
    /// timeline as JSON for the other ranks.
    TimelineSource keyedSource(std::string& timelineJson) const;
    void renderFilm();
    void cancelRender();
    void renderEnded(const FilmEnd& end);
    /// PNG frames in the film's frames directory.
    int keptFrames() const;
    int threads() const { return renderer_ ? renderer_->threads() : 0; }
    double nowS() const;
    std::string ranksText() const;

    Scene scene_;  ///< as loaded; the renderer owns its own copy
    TimelineSource source_;  ///< the scene's timeline as loaded (sections, --animation)
    anim::Timeline timeline_;        ///< what the window plays: the scene's, or the keys'
    anim::Timeline sceneTimeline_;   ///< the scene's own, back when the last key goes
    Film film_;
    RenderSettings settings_;
    ViewOptions options_;
    std::unique_ptr<FarmView> renderer_;
    ViewStats stats_;
    CameraKeys keys_;
    Aabb bounds_;
    Camera camera_;       ///< the free camera (valid once the user moved it or a frame came back)
    bool follow_ = true;  ///< show the timeline's camera
    Camera followCamera_;   ///< the timeline's camera at followFrame_
    int followFrame_ = -1;  ///< -1: followCamera_ is not known for the timeline shown
    int frame_ = 0;
    bool playing_ = false;
    bool dirty_ = false;  ///< the view changed since the last request
    std::optional<Clock::time_point> pendingInput_;
    uint64_t lastEpoch_ = 0, movingInFlight_ = 0;
    Clock::time_point start_;
    // Display and status.
    QImage picture_;
    int shownSpp_ = 0;
    double passMs_ = 0.0, fps_ = 0.0;
    int fpsFrames_ = 0;
    double fpsWindowStart_ = 0.0;
    bool tint_ = false;
    std::vector<uint8_t> tileRanks_;
    std::string message_;  ///< last action (saved, key added, error)
    ImageView* image_ = nullptr;
    QLabel* status_ = nullptr;
    QLabel* banner_ = nullptr;  ///< why the farm stopped, over the picture (hidden until then)
    QLabel* timeLabel_ = nullptr;
    QSlider* slider_ = nullptr;
    QPushButton* play_ = nullptr;
    QListWidget* keyList_ = nullptr;
    QTimer* restTimer_ = nullptr;
    QTimer* playTimer_ = nullptr;
    // The Render action: the film through runFarm on this window's ranks (film_render.h).
    bool filming_ = false;
    QPushButton* renderButton_ = nullptr;
    QProgressBar* renderBar_ = nullptr;
    std::string renderFramesDir_, renderOutput_;
    int renderTotal_ = 0;
    bool renderResumable_ = false;  ///< the last render was cancelled and the keys did not change since
    bool reportedError_ = false;
    friend class ImageView;
};

}  // namespace rf::view
