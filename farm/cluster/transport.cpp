#include "farm/cluster/transport.h"

#include "farm/cluster/launcher_reaper.h"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdlib>
#include <thread>
#include <vector>

#include <mpi.h>

namespace rf::farm {

namespace {

int64_t gBroadcastChunk = int64_t(1) << 30;  // 1 GiB, well below MPI's int count limit

void check(int rc, const std::string& what) {
    if (rc == MPI_SUCCESS) return;
    char msg[MPI_MAX_ERROR_STRING];
    int len = 0;
    MPI_Error_string(rc, msg, &len);
    throw TransportError(what + ": " + std::string(msg, len));
}

/// Whether a launcher (mpirun/mpiexec of Open MPI or MPICH, srun with PMI or PMIx) started this
/// process. A plain `rayfarm render` is one rank of one; it skips MPI_Init, whose singleton
/// start-up (forking Open MPI's orted) costs about a second, as long as a short film renders.
bool launchedByMpi() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
        if (std::getenv(v)) return true;
    return false;
}

/// Waits for a nonblocking collective, calling tick about every millisecond. Open MPI moves a
/// nonblocking collective on only inside MPI calls: while bytes flow (`flowing`) it is tested
/// without a pause, as fast as a blocking MPI_Bcast goes; the wait for root to start (it may
/// load a model for minutes) looks every half millisecond and leaves the core to the build.
void waitWatched(MPI_Request& request, const std::function<void()>& tick, bool flowing) {
    using Clock = std::chrono::steady_clock;
    auto lastTick = Clock::now();
    for (;;) {
        int done = 0;
        check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), "broadcast");
        if (done) return;
        const auto now = Clock::now();
        if (now - lastTick >= std::chrono::milliseconds(1)) {
            lastTick = now;
            tick();
        }
        if (!flowing) std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
}

}  // namespace

struct MpiTransport::Pending {
    std::string bytes;
    MPI_Request request = MPI_REQUEST_NULL;
    int dest = 0;
};

struct MpiTransport::Incoming {
    Message msg;
    MPI_Request request = MPI_REQUEST_NULL;
};

MpiTransport::MpiTransport() {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized && !launchedByMpi()) {
        solo_ = true;  // rank 0 of 1: nothing to send, receive or broadcast
        return;
    }
    if (!initialized) {
        int provided = 0;
        // One thread at a time calls MPI; render and encoder threads never do. SERIALIZED, not
        // FUNNELED: the viewer hands the transport to its film thread (runFarm) while its
        // window thread stays away from it.
        MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
    }
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    // mpirun --enable-recovery keeps the job going when a rank dies, and MPI_Finalize may then
    // wait for the dead rank (Open MPI 4.1.4: it did so once in a few runs, on a rank that died
    // unnoticed at the end). Leaving without it costs nothing there: mpirun takes it as it takes
    // every exit under recovery, without a word, and a rank's own sends are flushed first.
    if (const char* r = std::getenv("OMPI_MCA_orte_enable_recovery"))
        skipFinalize_ = std::string(r) == "1" || std::string(r) == "true" || std::string(r) == "yes" || std::string(r) == "on";
    // Tests shrink the broadcast chunk so that a small scene goes out in many pieces, as one
    // beyond 2 GiB must.
    if (const char* c = std::getenv("RAYFARM_BROADCAST_CHUNK")) setBroadcastChunk(std::atoll(c));
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    // Every rank's host name, once, so that a lost rank can be named with its host, and its
    // process, so that a rank on the same machine can see it end (processEnded).
    struct Card {
        char name[MPI_MAX_PROCESSOR_NAME] = {};
        ProcessIdentity process;
    } card;
    int len = 0;
    MPI_Get_processor_name(card.name, &len);
    card.process = ProcessIdentity::self();
    std::vector<Card> all(static_cast<size_t>(size_));
    if (MPI_Allgather(&card, int(sizeof card), MPI_BYTE, all.data(), int(sizeof card), MPI_BYTE, MPI_COMM_WORLD) == MPI_SUCCESS)
        for (Card& c : all) {
            c.name[MPI_MAX_PROCESSOR_NAME - 1] = '\0';
            hosts_.emplace_back(c.name);
            processes_.push_back(c.process);
        }
    MPI_Comm node;
    if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node) == MPI_SUCCESS) {
        MPI_Comm_size(node, &localRanks_);
        MPI_Comm_free(&node);
    }
}

MpiTransport::~MpiTransport() { finalize(); }

void MpiTransport::finalize() {
    if (finalized_) return;
    finalized_ = true;
    if (solo_) return;
    if (skipFinalize_) {
        flush(1.0);
        return;
    }
    flush(2.0);
    for (auto& p : pending_) MPI_Request_free(&p->request);
    pending_.clear();
    for (auto& in : incoming_) {
        MPI_Cancel(&in->request);
        MPI_Request_free(&in->request);
    }
    incoming_.clear();
    int fin = 0;
    MPI_Finalized(&fin);
    if (!fin) MPI_Finalize();
}

void MpiTransport::abort(int code) {
    if (solo_) std::_Exit(code);
    // MPI_Abort, and mpirun after it, may wait on a host cut off from the network; the user's
    // shell must not.
    armLauncherReaper(kLauncherGraceSeconds);
    std::thread([code] {
        std::this_thread::sleep_for(std::chrono::seconds(3));
        std::_Exit(code);
    }).detach();
    MPI_Abort(MPI_COMM_WORLD, code);
    std::_Exit(code);
}

bool MpiTransport::processEnded(int rank) const {
    return rank >= 0 && rank < int(processes_.size()) && lookAt(processes_[size_t(rank)]) == ProcessSeen::Ended;
}

std::string MpiTransport::host(int rank) const { return rank >= 0 && rank < int(hosts_.size()) ? hosts_[size_t(rank)] : ""; }

void MpiTransport::setBroadcastChunk(int64_t bytes) { gBroadcastChunk = std::max<int64_t>(1, bytes); }

void MpiTransport::send(int dest, int tag, std::string bytes) {
    if (solo_) throw TransportError("send to rank " + std::to_string(dest) + ": this process is the only rank");
    if (bytes.size() > size_t(INT_MAX)) throw TransportError("message to rank " + std::to_string(dest) + " exceeds 2 GiB");
    auto p = std::make_unique<Pending>();
    p->bytes = std::move(bytes);
    p->dest = dest;
    check(MPI_Isend(p->bytes.data(), int(p->bytes.size()), MPI_BYTE, dest, tag, MPI_COMM_WORLD, &p->request),
          "send to rank " + std::to_string(dest));
    pending_.push_back(std::move(p));
    progressSends();
}

void MpiTransport::progressSends() {
    for (auto it = pending_.begin(); it != pending_.end();) {
        // A send that failed went to a peer that is gone: dropped, as a send that never completes
        // is; the peer's silence tells the caller (rank 0 requeues a lost worker's work).
        int done = 0;
        const int rc = MPI_Test(&(*it)->request, &done, MPI_STATUS_IGNORE);
        it = done || rc != MPI_SUCCESS ? pending_.erase(it) : it + 1;
    }
}

bool MpiTransport::poll(Message& out) {
    if (solo_) return false;
    progressSends();
    // Every message that has begun to arrive gets a nonblocking receive. A blocking MPI_Recv
    // after a probe would wait forever for the rest of a large message whose sender's link was
    // cut; this way that sender just stays silent and the caller's timeout notices.
    for (int started = 0; started < 64; ++started) {
        int flag = 0;
        MPI_Message handle;
        MPI_Status st;
        check(MPI_Improbe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &handle, &st), "probe");
        if (!flag) break;
        int count = 0;
        check(MPI_Get_count(&st, MPI_BYTE, &count), "message size");
        auto in = std::make_unique<Incoming>();
        in->msg.source = st.MPI_SOURCE;
        in->msg.tag = st.MPI_TAG;
        in->msg.bytes.resize(size_t(count));
        check(MPI_Imrecv(in->msg.bytes.data(), count, MPI_BYTE, &handle, &in->request),
              "receive from rank " + std::to_string(st.MPI_SOURCE));
        incoming_.push_back(std::move(in));
    }
    // Hand out the oldest finished message whose sender has no older one still arriving, so each
    // sender's messages keep their order.
    std::vector<int> unfinished;
    for (auto it = incoming_.begin(); it != incoming_.end(); ++it) {
        const int source = (*it)->msg.source;
        if (std::find(unfinished.begin(), unfinished.end(), source) != unfinished.end()) continue;
        int done = 0;
        check(MPI_Test(&(*it)->request, &done, MPI_STATUS_IGNORE), "receive from rank " + std::to_string(source));
        if (!done) {
            unfinished.push_back(source);
            continue;
        }
        out = std::move((*it)->msg);
        incoming_.erase(it);
        return true;
    }
    return false;
}

bool MpiTransport::flush(double timeoutSeconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutSeconds);
    for (;;) {
        try {
            progressSends();
        } catch (const TransportError&) {
            return false;
        }
        if (pending_.empty()) return true;
        if (std::chrono::steady_clock::now() > end) return false;
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
}

void MpiTransport::broadcast(std::string& bytes, int root) {
    if (solo_) return;  // the only rank already holds root's bytes
    uint64_t n = bytes.size();
    check(MPI_Bcast(&n, 1, MPI_UINT64_T, root, MPI_COMM_WORLD), "broadcast");
    if (rank_ != root) bytes.resize(n);
    for (uint64_t off = 0; off < n;) {
        const int chunk = int(std::min<uint64_t>(n - off, uint64_t(gBroadcastChunk)));
        check(MPI_Bcast(bytes.data() + off, chunk, MPI_BYTE, root, MPI_COMM_WORLD), "broadcast");
        off += uint64_t(chunk);
    }
}

void MpiTransport::broadcastWatched(std::string& bytes, int root, const std::function<void()>& tick) {
    if (solo_) return;
    // As broadcast(), with MPI_Ibcast: a rank waiting for root (which may read a large model for
    // minutes first) keeps answering tick, and so can notice that root died.
    uint64_t n = bytes.size();
    MPI_Request request = MPI_REQUEST_NULL;
    check(MPI_Ibcast(&n, 1, MPI_UINT64_T, root, MPI_COMM_WORLD, &request), "broadcast");
    waitWatched(request, tick, false);
    if (rank_ != root) bytes.resize(n);
    for (uint64_t off = 0; off < n;) {
        const int chunk = int(std::min<uint64_t>(n - off, uint64_t(gBroadcastChunk)));
        check(MPI_Ibcast(bytes.data() + off, chunk, MPI_BYTE, root, MPI_COMM_WORLD, &request), "broadcast");
        waitWatched(request, tick, true);
        off += uint64_t(chunk);
    }
}

bool MpiTransport::take(int source, int tag, Message& out) {
    if (solo_) return false;
    int flag = 0;
    MPI_Message handle;
    MPI_Status st;
    check(MPI_Improbe(source, tag, MPI_COMM_WORLD, &flag, &handle, &st), "probe");
    if (!flag) return false;
    int count = 0;
    check(MPI_Get_count(&st, MPI_BYTE, &count), "message size");
    out.source = st.MPI_SOURCE;
    out.tag = st.MPI_TAG;
    out.bytes.resize(size_t(count));
    // Blocking: take() is for beats, whose few bytes travel with the envelope.
    check(MPI_Mrecv(out.bytes.data(), count, MPI_BYTE, &handle, MPI_STATUS_IGNORE), "receive from rank " + std::to_string(source));
    return true;
}

}  // namespace rf::farm
