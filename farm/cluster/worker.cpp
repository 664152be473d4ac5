#include "farm/cluster/worker.h"

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>
#include <vector>

#include <unistd.h>

#include "farm/process/interrupt.h"
#include "farm/cluster/master_watch.h"
#include "farm/cluster/messages.h"

namespace rf::farm {

void reportWorkerError(Transport& t, const std::string& message) {
    try {
        t.send(0, kTagError, message);
        t.flush(2.0);
    } catch (const TransportError&) {
        // Rank 0 is gone too; mpirun reports it.
    }
}

void awaitStop(Transport& t, double seconds) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    Message m;
    while (std::chrono::steady_clock::now() < until) {
        while (t.poll(m))
            if (m.source == 0 && m.tag == kTagStop) return;
        ::usleep(1000);
    }
}

namespace {

/// Test hook (mpi_render_test.sh poison-frame, docs/testing.md): the frame whose rendering
/// kills this worker, as a crash would (SIGKILL, once its heartbeat has named the frame); -1
/// when not set.
int crashFrameForTests() {
    const char* v = std::getenv("RAYFARM_TEST_CRASH_FRAME");
    return v && *v ? std::atoi(v) : -1;
}

/// Sends, a peer that is gone being no error here: rank 0 notices a lost worker by its
/// silence, a worker a lost rank 0 by rank 0's.
void sendQuietly(Transport& t, int dest, int tag, std::string bytes) {
    try {
        t.send(dest, tag, std::move(bytes));
    } catch (const TransportError&) {
    }
}

}  // namespace

int runWorker(Transport& t, RenderEngine& engine, double masterTimeout, const std::function<void(const Message&)>& other,
              ChunkWorkshop* shop, double firstWordTimeout) {
    using Clock = std::chrono::steady_clock;
    auto lastBeat = Clock::now() - std::chrono::seconds(1);
    Clock::time_point signalledAt{};
    bool signalled = false;
    bool viewing = false;    ///< a viewer's epochs have come: answer within a millisecond
    int lastItemPixels = 0;  ///< the size of the work coming in (a whole frame, or a tile)
    const int crashFrame = crashFrameForTests();
    if (firstWordTimeout <= 0.0) firstWordTimeout = 6 * masterTimeout;
    // Before its first word rank 0 may still be checking kept frames or building its BVH.
    MasterWatch master(t, masterTimeout, firstWordTimeout);
    for (;;) {
        const auto now = Clock::now();
        master.notePause(now);  // this worker was stopped, not rank 0
        if (!signalled && interruptSignal()) {
            // Finish nothing more: rank 0 is closing the video and only needs to know we live.
            signalled = true;
            signalledAt = now;
            engine.cancelQueued();
            if (shop) shop->cancel();
            lastBeat = now - std::chrono::seconds(1);
        }
        if (signalled && now - signalledAt > std::chrono::seconds(3)) return 130;

        Message m;
        // Work items that came together go to the engine together, so that small tiles of one
        // frame can be rendered at once (RenderEngine); any other message goes after them.
        std::vector<WorkItem> arrived;
        auto submitArrived = [&] {
            if (!arrived.empty()) engine.submitAll(std::exchange(arrived, {}));
        };
        while (t.poll(m)) {
            if (m.source == 0) master.heard(Clock::now());
            if (m.tag == kTagStop) return m.bytes == kStopAfterLoss ? kStopAfterLossExit : 0;
            if (m.tag == kTagWork) {
                if (signalled) continue;
                arrived.push_back(decodeWorkItem(m.bytes));
                lastItemPixels = arrived.back().rect.pixels();
                continue;
            }
            submitArrived();
            if (m.tag == kTagChunkAssemble && shop) {
                if (!signalled) shop->submitAssembly(decodeChunkOrder(m.bytes));
            } else if (m.tag == kTagTile && shop) {
                if (!signalled) shop->addTile(decodeTileResult(m.bytes));  // from the rank that rendered it
            } else if (m.tag == kTagView) {
                engine.setView(decodeViewSpec(m.bytes));
                viewing = true;
            }
            else if (m.tag != kTagAlive && other) other(m);
        }
        submitArrived();
        // Rank 0 is judged after the messages that came are read: a loop held up here (a large
        // send, a starved core) must not miss rank 0's beats already waiting, nor a stop it sent
        // before it ended. A stop of this process since the loop's top (the whole job paused
        // inside an MPI call) is a pause, as at the top, not rank 0's silence.
        // A signalled worker leaves within 3 s anyway (above), as the signal says.
        if (const std::string line = signalled ? std::string() : master.lost(Clock::now()); !line.empty()) {
            [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, line.data(), line.size());
            engine.cancelQueued();
            return kMasterSilentExit;
        }
        if (const std::string err = shop ? shop->error() : engine.error(); !err.empty()) {
            reportWorkerError(t, err);
            return 1;
        }
        if (crashFrame >= 0 && engine.currentFrame() == crashFrame) {
            sendQuietly(t, 0, kTagHeartbeat, encodeHeartbeat({crashFrame, 0, 0, engine.threads()}));
            t.flush(1.0);
            std::raise(SIGKILL);
        }
        if (now - lastBeat >= std::chrono::duration<double>(kHeartbeatSeconds)) {
            sendQuietly(t, 0, kTagHeartbeat, encodeHeartbeat({engine.currentFrame(), signalled ? 1 : 0, 0, engine.threads()}));
            lastBeat = now;
        }
        // Wait briefly for a result: short enough to answer messages promptly, long enough not
        // to spin a core the render threads need. Rank 0 keeps several items queued here
        // (credits), so looking every 2 ms for tiles and every 4 ms for whole frames never lets
        // the engine run dry, and wakes the core far less often than every millisecond did
        // (frame mode: 22k -> 8k context switches). A viewer's camera change must stop the
        // work in hand within a millisecond, so while viewing it looks every millisecond.
        const double wait = viewing ? 0.001 : lastItemPixels >= 100000 ? 0.004 : 0.002;
        if (shop) {
            for (ChunkWorkshop::Outgoing& o : shop->poll(wait))
                if (!signalled) sendQuietly(t, o.dest, o.tag, std::move(o.bytes));
        } else if (auto r = engine.takeResult(wait)) {
            if (!signalled) sendQuietly(t, 0, kTagResult, encodeTileResult(*r));
            while ((r = engine.takeResult()))
                if (!signalled) sendQuietly(t, 0, kTagResult, encodeTileResult(*r));
        }
    }
}

}  // namespace rf::farm
