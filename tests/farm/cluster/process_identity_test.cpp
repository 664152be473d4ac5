// A worker sees rank 0's process end when it runs under the same kernel (process_identity.h),
// and gives rank 0 up at once then, or after its silence otherwise (master_watch.h).
#include "farm/cluster/process_identity.h"

#include <chrono>
#include <csignal>
#include <cstring>
#include <thread>

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include "farm/cluster/loopback_transport.h"
#include "farm/cluster/master_watch.h"

using namespace rf::farm;

namespace {

/// A child that sends its identity up a pipe, then waits to be killed.
struct Child {
    pid_t pid = -1;
    ProcessIdentity id;
    Child() {
        int fds[2];
        EXPECT_EQ(::pipe(fds), 0);
        pid = ::fork();
        if (pid == 0) {
            const ProcessIdentity me = ProcessIdentity::self();
            [[maybe_unused]] const ssize_t n = ::write(fds[1], &me, sizeof me);
            for (;;) ::pause();
        }
        ::close(fds[1]);
        EXPECT_EQ(::read(fds[0], &id, sizeof id), ssize_t(sizeof id));
        ::close(fds[0]);
    }
    ~Child() {
        if (pid <= 0) return;
        ::kill(pid, SIGKILL);
        ::waitpid(pid, nullptr, 0);
    }
};

}  // namespace

TEST(ProcessIdentity, AProcessOnThisKernelIsSeenRunningThenEnded) {
    EXPECT_EQ(lookAt(ProcessIdentity::self()), ProcessSeen::Running);
    Child c;
    EXPECT_EQ(c.id.pid, c.pid);
    EXPECT_EQ(lookAt(c.id), ProcessSeen::Running);
    ::kill(c.pid, SIGSTOP);  // a stopped rank 0 is still there: its silence decides
    for (int i = 0; i < 100; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    EXPECT_EQ(lookAt(c.id), ProcessSeen::Running);
    ::kill(c.pid, SIGKILL);
    // Not yet reaped: a zombie has ended.
    siginfo_t info{};
    ASSERT_EQ(::waitid(P_PID, id_t(c.pid), &info, WEXITED | WNOWAIT), 0);
    EXPECT_EQ(lookAt(c.id), ProcessSeen::Ended);
    ::waitpid(c.pid, nullptr, 0);
    EXPECT_EQ(lookAt(c.id), ProcessSeen::Ended);
    c.pid = -1;
}

TEST(ProcessIdentity, APidHoldingAnotherProcessHasEndedAndAnotherKernelIsUnknown) {
    ProcessIdentity other = ProcessIdentity::self();
    other.startTicks += 1;  // the PID used again by a process started later
    EXPECT_EQ(lookAt(other), ProcessSeen::Ended);
    ProcessIdentity remote = ProcessIdentity::self();
    remote.boot[0] = remote.boot[0] == 'x' ? 'y' : 'x';  // another machine
    EXPECT_EQ(lookAt(remote), ProcessSeen::Unknown);
    ProcessIdentity container = ProcessIdentity::self();
    container.pidNamespace += 1;  // another PID namespace: its PIDs mean nothing here
    container.pid = 999999999;
    EXPECT_EQ(lookAt(container), ProcessSeen::Unknown);
}

namespace {

/// A worker's transport whose rank 0 ends when the test says.
class WatchedTransport : public LoopbackTransport {
public:
    using LoopbackTransport::LoopbackTransport;
    bool processEnded(int rank) const override { return rank == 0 && ended; }
    bool ended = false;
};

std::string lostWithin(MasterWatch& w, double seconds) {
    const auto end = MasterWatch::Clock::now() + std::chrono::duration<double>(seconds);
    while (MasterWatch::Clock::now() < end) {
        if (std::string line = w.lost(MasterWatch::Clock::now()); !line.empty()) return line;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return {};
}

}  // namespace

TEST(MasterWatch, RankZeroSeenEndedIsGivenUpAtOnceAndASilentOneAfterItsSilence) {
    LoopbackHub hub(2);
    WatchedTransport t(hub, 1);
    {
        MasterWatch w(t, 30.0, 30.0);
        w.heard(MasterWatch::Clock::now());
        EXPECT_EQ(lostWithin(w, 0.5), "");
        t.ended = true;
        const auto seen = MasterWatch::Clock::now();
        const std::string line = lostWithin(w, 3.0);
        const double took = std::chrono::duration<double>(MasterWatch::Clock::now() - seen).count();
        EXPECT_NE(line.find("rank 1 on "), std::string::npos) << line;
        EXPECT_NE(line.find("rank 0's process has ended (killed or crashed); this worker stops"), std::string::npos) << line;
        // Its last words (a stop already sent, mpirun's end of the job) get a second first.
        EXPECT_GE(took, 0.95);
        EXPECT_LT(took, 1.6);
    }
    t.ended = false;
    {
        MasterWatch w(t, 0.4, 3.0);
        EXPECT_EQ(lostWithin(w, 0.8), "");  // before its first word rank 0 gets firstWord
        w.heard(MasterWatch::Clock::now());
        const std::string line = lostWithin(w, 2.0);
        EXPECT_NE(line.find("rank 0 has been silent for 0."), std::string::npos) << line;
    }
}
