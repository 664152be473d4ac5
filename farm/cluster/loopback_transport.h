#pragma once
/// In-process transport: N ranks as threads (or as objects stepped by one thread) exchanging
/// messages through shared mailboxes. For tests of the master and worker loops without mpirun.
#include <condition_variable>
#include <mutex>
#include <vector>

#include "farm/cluster/transport.h"

namespace rf::farm {

/// Mailboxes of every rank.
class LoopbackHub {
public:
    explicit LoopbackHub(int ranks) : boxes_(size_t(ranks)) {}
    int size() const { return int(boxes_.size()); }

    void post(int dest, Message m) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (dead_.size() > size_t(dest) && dead_[size_t(dest)]) return;  // a dead rank receives nothing
        boxes_.at(size_t(dest)).push_back(std::move(m));
        cv_.notify_all();
    }
    /// First message for rank matching tag (any tag if tag == 0); waits if `wait`.
    bool take(int rank, int tag, Message& out, bool wait) {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            auto& box = boxes_.at(size_t(rank));
            for (auto it = box.begin(); it != box.end(); ++it) {
                if (tag == 0 ? it->tag > 0 : it->tag == tag) {
                    out = std::move(*it);
                    box.erase(it);
                    return true;
                }
            }
            if (!wait) return false;
            cv_.wait(lock);
        }
    }
    /// Simulates a rank that vanished: messages to it are dropped.
    void kill(int rank) {
        std::lock_guard<std::mutex> lock(mutex_);
        dead_.resize(boxes_.size(), false);
        dead_[size_t(rank)] = true;
    }

private:
    std::mutex mutex_;
    std::condition_variable cv_;
    std::vector<std::deque<Message>> boxes_;
    std::vector<bool> dead_;
};

/// One rank's view of a LoopbackHub.
class LoopbackTransport : public Transport {
public:
    LoopbackTransport(LoopbackHub& hub, int rank) : hub_(hub), rank_(rank) {}
    int rank() const override { return rank_; }
    int size() const override { return hub_.size(); }
    int ranksOnThisNode() const override { return hub_.size(); }  // every rank is a thread here
    // Not inlined: under LTO, GCC 12 inlines this into the master's dispatch, sees the work item's
    // constant length, and takes the moved string for one copied into its 16-byte small buffer
    // (a false -Wstringop-overflow). Test-only transport, so the call costs nothing that matters.
    [[gnu::noinline]] void send(int dest, int tag, std::string bytes) override {
        hub_.post(dest, {rank_, tag, std::move(bytes)});
    }
    bool poll(Message& out) override { return hub_.take(rank_, 0, out, false); }
    bool flush(double) override { return true; }
    void broadcast(std::string& bytes, int root) override {
        constexpr int kTagBroadcast = -1;  // negative: never seen by poll()
        if (rank_ == root) {
            for (int r = 0; r < size(); ++r)
                if (r != root) hub_.post(r, {rank_, kTagBroadcast, bytes});
        } else {
            Message m;
            hub_.take(rank_, kTagBroadcast, m, true);
            bytes = std::move(m.bytes);
        }
    }

private:
    LoopbackHub& hub_;
    int rank_;
};

}  // namespace rf::farm
