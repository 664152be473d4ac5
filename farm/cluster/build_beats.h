#pragma once
/// A worker building its scene (parsing the files, decoding textures, filtering the
/// environment, building the BVH) is alive: it tells rank 0 so, as a rendering worker does, with
/// a heartbeat every kHeartbeatSeconds marked `building`, sent from a thread of its own while the
/// main thread builds. Rank 0's liveness rule then counts it busy, and a slow build is never
/// reported as a dead rank ("rank 1 stopped answering").
///
/// Rank 0, loading the scene (a huge model may take minutes before the broadcast), says it is
/// alive the same way to every worker (kTagAlive), so that a worker waiting for the scene can
/// tell a long load from a dead rank 0 (master_watch.h).
///
/// MPI is initialised MPI_THREAD_SERIALIZED: one thread at a time. The main thread makes no MPI
/// call while it builds, and the beats stop (the thread is joined) before it makes the next.
#include <condition_variable>
#include <mutex>
#include <thread>

#include "farm/cluster/transport.h"

namespace rf::farm {

class BuildBeats {
public:
    /// Starts beating: to rank 0 on a worker, to every worker on rank 0 (nothing on a lone rank).
    explicit BuildBeats(Transport& t);
    /// Stops and joins: the caller's thread may use the transport again.
    ~BuildBeats();
    BuildBeats(const BuildBeats&) = delete;
    BuildBeats& operator=(const BuildBeats&) = delete;

private:
    void beat();

    Transport& t_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stop_ = false;
    std::thread thread_;
};

/// Rank 0's beat to every worker (kTagAlive), from the thread that may use the transport.
void sayAlive(Transport& t);

}  // namespace rf::farm
