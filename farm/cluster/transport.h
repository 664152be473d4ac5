#pragma once
/// A thin interface over MPI point-to-point and broadcast, so the master and worker loops can be
/// unit-tested in one process (LoopbackHub) and run for real under mpirun (MpiTransport).
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "farm/cluster/process_identity.h"

namespace rf::farm {

/// A message as received: who sent it, its tag (messages.h) and its payload.
struct Message {
    int source = -1;
    int tag = 0;
    std::string bytes;
};

/// Communication failed (a peer is gone, MPI reported an error).
class TransportError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class Transport {
public:
    virtual ~Transport() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;
    /// Queues bytes for dest and returns without waiting for the receiver.
    virtual void send(int dest, int tag, std::string bytes) = 0;
    /// Takes one waiting message from any rank, if there is one; never blocks.
    virtual bool poll(Message& out) = 0;
    /// Waits up to timeoutSeconds for queued sends to complete; false if some did not.
    virtual bool flush(double timeoutSeconds) = 0;
    /// Collective: every rank ends with root's bytes (any size; sent in chunks below 2 GiB).
    virtual void broadcast(std::string& bytes, int root) = 0;
    /// broadcast() that calls `tick` every millisecond or so while it waits, on every rank, so
    /// that root can say it is alive and the others can watch it (a tick may throw to give up;
    /// the transport is then good only for leaving). Here: broadcast(), tick never called.
    virtual void broadcastWatched(std::string& bytes, int root, const std::function<void()>& tick) {
        (void)tick;
        broadcast(bytes, root);
    }
    /// Takes one waiting message from `source` with `tag`, if there is one, leaving every other
    /// message where it is; never blocks. Only for messages without payload order concerns (a
    /// beat). Here: none.
    virtual bool take(int source, int tag, Message& out) {
        (void)source, (void)tag, (void)out;
        return false;
    }
    /// True when this process can see that rank's process has ended (the same kernel: the same
    /// machine); false when it runs, or cannot be seen (process_identity.h).
    virtual bool processEnded(int rank) const {
        (void)rank;
        return false;
    }
    /// Ranks sharing this rank's node (for sharing its cores among them).
    virtual int ranksOnThisNode() const { return 1; }
    /// The host a rank runs on, for messages about it ("" if unknown).
    virtual std::string host(int /*rank*/) const { return {}; }
};

/// MPI_COMM_WORLD, with MPI_ERRORS_RETURN so a failing peer becomes a TransportError rather than
/// an abort deep inside MPI. A process no MPI launcher started is rank 0 of 1 and never
/// initialises MPI (its singleton start-up costs a second). One thread at a time may use it
/// (MPI_THREAD_SERIALIZED).
class MpiTransport : public Transport {
public:
    /// How long mpirun gets to end the job after rank 0 aborts (it takes well under a second
    /// when every host answers).
    static constexpr double kLauncherGraceSeconds = 2.5;
    MpiTransport();
    ~MpiTransport() override;
    int rank() const override { return rank_; }
    int size() const override { return size_; }
    void send(int dest, int tag, std::string bytes) override;
    bool poll(Message& out) override;
    bool flush(double timeoutSeconds) override;
    void broadcast(std::string& bytes, int root) override;
    void broadcastWatched(std::string& bytes, int root, const std::function<void()>& tick) override;
    bool take(int source, int tag, Message& out) override;
    bool processEnded(int rank) const override;
    std::string host(int rank) const override;

    int ranksOnThisNode() const override { return localRanks_; }
    /// Largest chunk one MPI_Bcast carries; tests lower it to exercise chunking.
    static void setBroadcastChunk(int64_t bytes);
    /// Ends every rank at once (a worker is lost, nothing better left to do). Leaves this
    /// process within a few seconds even if MPI_Abort cannot reach every host, and ends mpirun
    /// kLauncherGraceSeconds later if it still waits for one (launcher_reaper.h).
    [[noreturn]] void abort(int code);
    /// Ends MPI normally (also done by the destructor).
    void finalize();
    /// A rank of the job was lost and the run went on without it: finalize() then only flushes
    /// (for a second) and leaves MPI as it is, since MPI_Finalize would wait for the lost rank.
    void skipFinalize() { skipFinalize_ = true; }

private:
    struct Pending;
    struct Incoming;
    void progressSends();
    int rank_ = 0, size_ = 1, localRanks_ = 1;
    std::vector<std::string> hosts_;  // by rank
    std::vector<ProcessIdentity> processes_;  // by rank
    bool finalized_ = false;
    bool skipFinalize_ = false;
    bool solo_ = false;  ///< not started by an MPI launcher: one rank, MPI never initialised
    std::deque<std::unique_ptr<Pending>> pending_;
    std::deque<std::unique_ptr<Incoming>> incoming_;  // receives begun, in arrival order
};

}  // namespace rf::farm
