#include "farm/cluster/build_beats.h"

#include <chrono>

#include "farm/process/interrupt.h"
#include "farm/cluster/messages.h"

namespace rf::farm {

BuildBeats::BuildBeats(Transport& t) : t_(t) {
    if (t_.size() > 1) thread_ = std::thread([this] { beat(); });
}

BuildBeats::~BuildBeats() {
    if (!thread_.joinable()) return;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void BuildBeats::beat() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
        if (t_.rank() == 0) {
            sayAlive(t_);
            wake_.wait_for(lock, std::chrono::duration<double>(kHeartbeatSeconds), [this] { return stop_; });
            continue;
        }
        Heartbeat h;
        h.signalled = interruptSignal() ? 1 : 0;
        h.building = 1;
        try {
            t_.send(0, kTagHeartbeat, encodeHeartbeat(h));
        } catch (const TransportError&) {
            return;  // rank 0 is gone; the build's end finds out the rest
        }
        wake_.wait_for(lock, std::chrono::duration<double>(kHeartbeatSeconds), [this] { return stop_; });
    }
}

void sayAlive(Transport& t) {
    for (int r = 1; r < t.size(); ++r) {
        try {
            t.send(r, kTagAlive, std::string());
        } catch (const TransportError&) {
            // That worker is gone: rank 0 finds out by its silence.
        }
    }
}

}  // namespace rf::farm
