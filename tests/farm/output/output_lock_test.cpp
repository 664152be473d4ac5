// OutputLock (farm/output/output_lock.h) on the real file system: a live holder refuses, a dead,
// rebooted or reused one is taken over, another host's is refused, and a fcntl lock held on the
// file counts as alive whatever the file says. Two processes racing: output_guard_test.sh.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include "farm/output/output_lock.h"
#include "farm/process/usage_error.h"

using rf::OutputLock;

namespace {

std::string freshDir(const std::string& name) {
    const std::string d = std::string(RAYFARM_TEST_OUT) + "/output_lock/" + name;
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

std::string readFile(const std::string& p) {
    std::ifstream f(p);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

void writeFile(const std::string& p, const std::string& s) { std::ofstream(p) << s; }

std::string host() {
    char b[256] = {};
    gethostname(b, sizeof b - 1);
    return b;
}

std::string bootId() {
    std::ifstream f("/proc/sys/kernel/random/boot_id");
    std::string s;
    std::getline(f, s);
    return s;
}

/// A pid that ran and is gone: a child that exited and was reaped.
long deadPid() {
    const pid_t c = fork();
    if (c == 0) _exit(0);
    waitpid(c, nullptr, 0);
    return long(c);
}

std::string refusal(const std::string& path) {
    try {
        OutputLock second(path);
    } catch (const rf::UsageError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(OutputLock, SecondLockOnTheSameOutputIsRefusedNamingTheHolder) {
    const std::string out = freshDir("second") + "/a.mp4";
    {
        OutputLock first(out);
        EXPECT_TRUE(std::filesystem::exists(out + ".lock"));
        const std::string why = refusal(out);
        EXPECT_NE(why.find(out + ": another render is writing it (pid " + std::to_string(getpid()) + " on " + host() + " since "),
                  std::string::npos)
            << why;
        EXPECT_EQ(readFile(out + ".lock").rfind("rayfarm-lock " + host() + " " + std::to_string(getpid()) + " ", 0), 0u);
    }
    EXPECT_FALSE(std::filesystem::exists(out + ".lock")) << "released at the end";
    OutputLock again(out);  // and free again
    EXPECT_TRUE(again.held());
}

TEST(OutputLock, DirectoryLockSitsBesideIt) {
    const std::string dir = freshDir("dir") + "/a.frames/";
    EXPECT_EQ(rf::lockPathFor(dir), dir.substr(0, dir.size() - 1) + ".lock");
    OutputLock l(dir);
    EXPECT_TRUE(std::filesystem::exists(rf::lockPathFor(dir)));
    EXPECT_FALSE(std::filesystem::exists(dir)) << "the lock does not create the directory";
}

TEST(OutputLock, DeadHolderOnThisHostIsTakenOver) {
    const std::string out = freshDir("dead") + "/a.mp4";
    const long pid = deadPid();
    writeFile(out + ".lock", "rayfarm-lock " + host() + " " + std::to_string(pid) + " - " + bootId() + " 1796400000\n");
    std::string note;
    OutputLock l(out, &note);
    EXPECT_EQ(note, out + ": took over the lock of pid " + std::to_string(pid) + " on " + host() + " (no longer running)");
    EXPECT_EQ(readFile(out + ".lock").rfind("rayfarm-lock " + host() + " " + std::to_string(getpid()) + " ", 0), 0u);
}

TEST(OutputLock, ReusedPidAndRebootedHostAreStale) {
    const std::string dir = freshDir("reused");
    // Our own pid (alive) but another start time: the pid was reused since.
    writeFile(dir + "/a.mp4.lock", "rayfarm-lock " + host() + " " + std::to_string(getpid()) + " 1 " + bootId() + " 0\n");
    std::string note;
    OutputLock a(dir + "/a.mp4", &note);
    EXPECT_NE(note.find("its pid now belongs to another process"), std::string::npos) << note;
    // Alive, but written in an earlier boot of this host.
    writeFile(dir + "/b.mp4.lock", "rayfarm-lock " + host() + " " + std::to_string(getppid()) + " - 00000000-old-boot 0\n");
    note.clear();
    OutputLock b(dir + "/b.mp4", &note);
    EXPECT_NE(note.find("this host rebooted since"), std::string::npos) << note;
}

TEST(OutputLock, LiveHolderOnThisHostIsRefusedWithoutAFcntlLock) {
    const std::string dir = freshDir("live");
    // The parent process: alive, its start time unknown to the file ("-").
    writeFile(dir + "/a.mp4.lock", "rayfarm-lock " + host() + " " + std::to_string(getppid()) + " - " + bootId() + " 0\n");
    const std::string why = refusal(dir + "/a.mp4");
    EXPECT_NE(why.find("another render is writing it (pid " + std::to_string(getppid()) + " on " + host()), std::string::npos) << why;
}

TEST(OutputLock, AnotherHostsLockIsNeverTakenOver) {
    const std::string dir = freshDir("remote");
    const std::string content = "rayfarm-lock farm9.example 4242 - - 1796400000\n";
    writeFile(dir + "/a.mp4.lock", content);
    const std::string why = refusal(dir + "/a.mp4");
    EXPECT_NE(why.find("another render is writing it (pid 4242 on farm9.example since 2026-12-04 "), std::string::npos) << why;
    EXPECT_EQ(readFile(dir + "/a.mp4.lock"), content);
}

TEST(OutputLock, AFcntlLockHeldCountsAsAliveWhateverTheFileSays) {
    const std::string out = freshDir("fcntl") + "/a.mp4";
    OutputLock first(out);
    // The file now claims a dead holder (a pid namespace apart, say): the fcntl lock still tells.
    const long pid = deadPid();
    writeFile(out + ".lock.tmp", "rayfarm-lock " + host() + " " + std::to_string(pid) + " - - 0\n");
    // Same inode (the fcntl lock is on it): rewrite in place.
    writeFile(out + ".lock", readFile(out + ".lock.tmp"));
    const std::string why = refusal(out);
    EXPECT_NE(why.find("another render is writing it (pid " + std::to_string(pid)), std::string::npos) << why;
}

// Issue 46 #5: a resume typed the moment an interrupted run prints its line waits for that run,
// which is still closing its video, instead of being refused; a holder not ending is refused
// at once as before.
TEST(OutputLock, AnEndingHolderIsWaitedForAndALiveOneIsNot) {
    const std::string out = freshDir("ending") + "/a.mp4";
    int ready[2], go[2];
    ASSERT_EQ(pipe(ready), 0);
    ASSERT_EQ(pipe(go), 0);
    const pid_t child = fork();
    if (child == 0) {
        OutputLock held(out);
        held.markEnding();
        char c = 1;
        (void)!write(ready[1], &c, 1);
        (void)!read(go[0], &c, 1);  // the parent's clock runs from here: a late parent cannot shorten the wait
        usleep(800 * 1000);         // closing its video
        held.release();
        _exit(0);
    }
    char c = 0;
    ASSERT_EQ(read(ready[0], &c, 1), 1);
    EXPECT_NE(readFile(out + ".lock").find(" ending\n"), std::string::npos) << readFile(out + ".lock");
    const auto start = std::chrono::steady_clock::now();
    ASSERT_EQ(write(go[1], &c, 1), 1);
    std::string note;
    OutputLock after(out, &note);  // waits, then takes the lock the child let go
    const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_TRUE(after.held());
    EXPECT_GT(waited, 0.3);
    EXPECT_LT(waited, rf::kEndingWaitSeconds);
    EXPECT_EQ(readFile(out + ".lock").rfind("rayfarm-lock " + host() + " " + std::to_string(getpid()) + " ", 0), 0u);
    waitpid(child, nullptr, 0);
    close(ready[0]);
    close(ready[1]);
    close(go[0]);
    close(go[1]);

    // Not ending: refused at once.
    const std::string other = freshDir("not-ending") + "/b.mp4";
    OutputLock live(other);
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_NE(refusal(other).find("another render is writing it"), std::string::npos);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 0.3);
}
