// The window's authoring side: camera keys (add, list, jump, delete) and saving the scene with
// its keyed timeline.
#include <QListWidget>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "view_window.h"

namespace rf::view {

void ViewWindow::addKey() {
    const double t = timeline_.frameTime(frame_);
    keys_.add(keyFromCamera(camera_, scene_.renderOrigin, t));
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
    std::string json = scene_.timelineJson;
    if (keys_.empty()) {
        timeline_ = sceneTimeline_;
    } else {
        Scene keyed = scene_;
        json = keyed.timelineJson = nlohmann::json{{"timeline", keyedTimeline(keys_, scene_, film_)}}.dump();
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
