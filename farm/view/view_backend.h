#pragma once
/// What the window renders with: its own threads (ViewRenderer) or the farm's ranks
/// (FarmView). Both take the latest view, cancel older work and publish ViewFrames.
#include <cstdint>
#include <string>

#include "view_frame.h"

namespace rf::view {

class ViewBackend {
public:
    virtual ~ViewBackend() = default;
    /// Replaces whatever is pending or rendering; returns the request's epoch.
    virtual uint64_t request(const ViewRequest& r) = 0;
    /// Plays another timeline from the next request on (timelineJson: {"timeline": …} as in
    /// Scene::timeline, serialised), over the scene as loaded.
    virtual void setTimeline(const anim::Timeline& tl, const std::string& timelineJson) = 0;
    /// What stopped the rendering (a render error, a lost rank); empty while all is well.
    virtual std::string error() const = 0;
    virtual int threads() const = 0;
    virtual int ranks() const { return 1; }
    /// Work done on the window's thread (the farm's messages); the window calls it every
    /// millisecond or so when wantsSteps().
    virtual void step() {}
    virtual bool wantsSteps() const { return false; }
    /// After a film render borrowed the ranks (nothing was stepped meanwhile): forget the work
    /// that was out and start listening afresh.
    virtual void resumeAfterFilm() {}
    /// After a SIGTERM from mpirun: the rank that did not answer it within `seconds` ("rank N"),
    /// or "" (all answered, or there are no other ranks).
    virtual std::string findSilentRank(double /*seconds*/) { return ""; }
};

}  // namespace rf::view
