#pragma once
/// The window's frames rendered across the farm's ranks (rank 0 of `mpirun … rayfarm view`):
/// every pass is split into 64×64 work items handed to ranks 1…N−1 (pixel mode), a few in
/// flight per rank, pixels assembled on rank 0. All transport calls happen in step(), on the
/// thread that owns the transport (the window's). A new request starts a new epoch: the ranks
/// drop older work as soon as it reaches them, and late tiles of older epochs are ignored.
#include <map>
#include <string>
#include <vector>

#include "transport.h"
#include "view_backend.h"
#include "view_messages.h"

namespace rf::view {

class FarmView : public ViewBackend {
public:
    /// t: rank 0's transport, with at least one other rank serving runViewWorker.
    FarmView(farm::Transport& t, RenderSettings settings, int threadsPerRank, Publish publish);
    /// Tells every rank to stop and waits (≤ 1 s) for the message to leave.
    ~FarmView() override;

    uint64_t request(const ViewRequest& r) override;
    void setTimeline(const anim::Timeline& tl, const std::string& timelineJson) override;
    std::string error() const override { return error_; }
    int threads() const override { return threadsPerRank_; }
    int ranks() const override { return t_.size(); }
    void step() override;
    bool wantsSteps() const override { return true; }
    void resumeAfterFilm() override;
    /// After mpirun's SIGTERM (it ends the whole job when a rank dies): listens up to
    /// `seconds` for every rank's signalled heartbeat and returns "rank N" for the first that
    /// stays silent (the one that died), or "" if all answered (a plain Ctrl-C).
    std::string findSilentRank(double seconds) override;

    static constexpr int kWorkTile = 64;
    static constexpr int kInFlightPerRank = 3;
    /// A rank silent this long while it holds work is reported lost.
    static constexpr double kSilenceSeconds = 5.0;

private:
    void startPass();
    void dispatch();
    void take(const farm::Message& m);
    void finishPass();
    void publishNow(bool complete);

    farm::Transport& t_;
    RenderSettings settings_;
    int threadsPerRank_;
    Publish publish_;
    std::string error_;
    uint64_t epoch_ = 0;
    bool active_ = false;     ///< a request is being rendered
    ViewRequest request_;
    std::vector<int> passes_;  ///< spp of each pass of this request
    size_t pass_ = 0;
    int scale_ = 1;
    std::vector<TileRect> tiles_;
    size_t nextTile_ = 0, tilesDone_ = 0;
    std::map<int, int> inFlight_;          ///< rank → work items of the current epoch out
    std::map<int, Clock::time_point> heard_;  ///< rank → last message
    ViewFrame frame_;
    Clock::time_point passStart_, lastPublish_;
    bool stopped_ = false;
};

}  // namespace rf::view
