#include "worker.h"

#include <chrono>

#include "interrupt.h"
#include "messages.h"

namespace rf::farm {

void reportWorkerError(Transport& t, const std::string& message) {
    try {
        t.send(0, kTagError, message);
        t.flush(2.0);
    } catch (const TransportError&) {
        // Rank 0 is gone too; mpirun reports it.
    }
}

int runWorker(Transport& t, RenderEngine& engine) {
    using Clock = std::chrono::steady_clock;
    auto lastBeat = Clock::now() - std::chrono::seconds(1);
    Clock::time_point signalledAt{};
    bool signalled = false;
    for (;;) {
        const auto now = Clock::now();
        if (!signalled && interruptSignal()) {
            // Finish nothing more: rank 0 is closing the video and only needs to know we live.
            signalled = true;
            signalledAt = now;
            engine.cancelQueued();
            lastBeat = now - std::chrono::seconds(1);
        }
        if (signalled && now - signalledAt > std::chrono::seconds(3)) return 130;

        Message m;
        while (t.poll(m)) {
            if (m.tag == kTagStop) return 0;
            if (m.tag == kTagWork && !signalled) engine.submit(decodeWorkItem(m.bytes));
        }
        if (const std::string err = engine.error(); !err.empty()) {
            reportWorkerError(t, err);
            return 1;
        }
        if (now - lastBeat >= std::chrono::duration<double>(kHeartbeatSeconds)) {
            t.send(0, kTagHeartbeat, encodeHeartbeat({engine.currentFrame(), signalled ? 1 : 0}));
            lastBeat = now;
        }
        // Wait briefly for a result: short enough to answer messages promptly, long enough not
        // to spin a core the render threads need.
        if (auto r = engine.takeResult(0.001)) {
            if (!signalled) t.send(0, kTagResult, encodeTileResult(*r));
            while ((r = engine.takeResult()))
                if (!signalled) t.send(0, kTagResult, encodeTileResult(*r));
        }
    }
}

}  // namespace rf::farm
