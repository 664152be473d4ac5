#include "farm/output/output_lock.h"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <chrono>
#include <ctime>
#include <thread>
#include <fstream>
#include <sstream>
#include <utility>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "engine/util/file_source.h"
#include "farm/process/usage_error.h"

namespace rf {

namespace {

std::string hostName() {
    char buf[256] = {};
    if (::gethostname(buf, sizeof buf - 1) != 0 || !buf[0]) return "unknown-host";
    std::string h = buf;
    for (char& c : h)
        if (c == ' ' || c == '\n' || c == '\t') c = '_';
    return h;
}

std::string firstLineOf(const std::string& path) {
    std::ifstream f(path);
    std::string line;
    std::getline(f, line);
    return line;
}

/// The kernel's id of this boot: a host that rebooted since a lock was written has no holder.
std::string bootId() { return firstLineOf("/proc/sys/kernel/random/boot_id"); }

/// When process pid started (clock ticks since boot, /proc/PID/stat field 22); "" if unknown.
/// With the pid it names one process for the life of the boot, even after the pid is reused.
std::string startTimeOf(long pid) {
    const std::string stat = firstLineOf("/proc/" + std::to_string(pid) + "/stat");
    const size_t paren = stat.rfind(')');  // the command name may hold spaces and parentheses
    if (paren == std::string::npos) return "";
    std::istringstream in(stat.substr(paren + 1));
    std::string field;
    for (int i = 3; i <= 22 && in >> field; ++i)
        if (i == 22) return field;
    return "";
}

/// What a lock file says about its holder.
struct Holder {
    bool parsed = false;
    std::string host, start, boot;
    long pid = 0;
    long long since = 0;
    bool ending = false;  ///< its run is winding down (markEnding)
};

Holder parseHolder(const std::string& content) {
    Holder h;
    std::istringstream in(content);
    std::string magic;
    if (in >> magic >> h.host >> h.pid >> h.start >> h.boot >> h.since && magic == "rayfarm-lock" && h.pid > 0) h.parsed = true;
    std::string state;
    if (h.parsed && in >> state && state == "ending") h.ending = true;
    return h;
}

std::string readAll(const std::string& path, bool& ok) {
    std::ifstream f(path, std::ios::binary);
    ok = bool(f);
    return ok ? std::string(std::istreambuf_iterator<char>(f), {}) : std::string();
}

std::string utcTime(long long seconds) {
    const std::time_t t = std::time_t(seconds);
    std::tm tm{};
    char buf[40];
    if (!gmtime_r(&t, &tm) || !std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S UTC", &tm)) return "an unknown time";
    return buf;
}

#ifdef F_OFD_SETLK
constexpr int kSetLock = F_OFD_SETLK, kGetLock = F_OFD_GETLK;  // per open file: also across threads of one process
#else
constexpr int kSetLock = F_SETLK, kGetLock = F_GETLK;
#endif

struct flock wholeFile(short type) {
    struct flock fl {};
    fl.l_type = type;
    fl.l_whence = SEEK_SET;
    return fl;
}

/// Whether some process holds a fcntl lock on the file (false where the file system has none).
bool heldByFcntl(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    struct flock fl = wholeFile(F_WRLCK);
    const bool held = ::fcntl(fd, kGetLock, &fl) == 0 && fl.l_type != F_UNLCK;
    ::close(fd);
    return held;
}

/// Whether the holder is known to be gone. Only this host's processes can be looked at.
bool isStale(const Holder& h, const std::string& host, const std::string& boot, std::string& why) {
    if (h.host != host) return false;
    if (!boot.empty() && h.boot != "-" && h.boot != boot) {
        why = "this host rebooted since";
        return true;
    }
    if (::kill(pid_t(h.pid), 0) != 0 && errno == ESRCH) {
        why = "no longer running";
        return true;
    }
    const std::string start = startTimeOf(h.pid);
    if (h.start != "-" && !start.empty() && start != h.start) {
        why = "no longer running; its pid now belongs to another process";
        return true;
    }
    return false;
}

/// Creates `path` holding `content`, failing if it exists (errno EEXIST).
bool createExclusive(const std::string& path, const std::string& content) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) return false;
    const bool ok = ::write(fd, content.data(), content.size()) == ssize_t(content.size());
    const int err = errno;
    if (::close(fd) != 0 || !ok) {
        ::unlink(path.c_str());
        errno = ok ? EIO : err;
        return false;
    }
    return true;
}

[[noreturn]] void cannotLock(const std::string& lockPath, int err) {
    throw UsageError(lockPath + ": cannot create the lock: " + std::strerror(err));
}

/// Publishes `content` at lockPath atomically: written under a unique name, then link()ed.
/// True if this process now holds lockPath; false if it exists (someone holds it).
bool publish(const std::string& lockPath, const std::string& content, const std::string& unique) {
    ::unlink(unique.c_str());  // a leftover of this pid's earlier life
    if (!createExclusive(unique, content)) cannotLock(lockPath, errno);
    const int rc = ::link(unique.c_str(), lockPath.c_str());
    const int err = errno;
    struct stat st {};
    // NFS: a link whose reply was lost is retried by the client and answered EEXIST, though it
    // was made; the link count of the unique file tells.
    const bool linked = rc == 0 || (::stat(unique.c_str(), &st) == 0 && st.st_nlink == 2);
    ::unlink(unique.c_str());
    if (linked) return true;
    if (err == EEXIST) return false;
    if (err == EPERM || err == EOPNOTSUPP || err == ENOSYS) {  // no hard links here (vfat, some FUSE)
        if (createExclusive(lockPath, content)) return true;
        if (errno == EEXIST) return false;
        cannotLock(lockPath, errno);
    }
    cannotLock(lockPath, err);
}

}  // namespace

std::string lockPathFor(const std::string& path) {
    std::string p = path;
    while (p.size() > 1 && p.back() == '/') p.pop_back();
    return p + ".lock";
}

OutputLock::OutputLock(const std::string& path, std::string* note) {
    const std::string lockPath = lockPathFor(path);
    const std::string host = hostName(), boot = bootId();
    const long pid = long(::getpid());
    const std::string start = startTimeOf(pid);
    const std::string content = "rayfarm-lock " + host + " " + std::to_string(pid) + " " + (start.empty() ? "-" : start) + " " +
                                (boot.empty() ? "-" : boot) + " " + std::to_string((long long)std::time(nullptr)) + "\n";
    const std::string unique = lockPath + "." + host + "." + std::to_string(pid);
    using Clock = std::chrono::steady_clock;
    const auto waitUntil = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kEndingWaitSeconds));
    for (int attempt = 0; attempt < 50; ++attempt) {
        if (publish(lockPath, content, unique)) {
            lockPath_ = lockPath;
            content_ = content;
            fd_ = ::open(lockPath.c_str(), O_RDWR | O_CLOEXEC);
            if (fd_ >= 0) {
                struct flock fl = wholeFile(F_WRLCK);
                (void)::fcntl(fd_, kSetLock, &fl);  // a file system without locks keeps the link() lock alone
            }
            return;
        }
        // A directory (or a FIFO, ...) where the lock goes is no lock: reading it would fail
        // ("Is a directory") or wait for a writer for good. Not followed: a lock is never a link.
        if (const std::string what = notRegularFile(lockPath, /*followLinks=*/false); !what.empty())
            throw UsageError(lockPath + ": is " + what + ", not a lock file; remove it if no render is writing " + path);
        bool ok = false;
        const std::string theirs = readAll(lockPath, ok);
        if (!ok) continue;  // released in between: try again
        const Holder h = parseHolder(theirs);
        std::string why;
        if (!h.parsed) {
            // Written by link() whole, so a half file is no rayfarm lock: a young one may be
            // another tool's in the middle of writing, an old one is debris.
            struct stat st {};
            if (::stat(lockPath.c_str(), &st) == 0 && std::time(nullptr) - st.st_mtime < 10)
                throw UsageError(path + ": its lock file " + lockPath + " is not rayfarm's; remove it if no render is writing " + path);
            why = "unreadable";
        }
        if (heldByFcntl(lockPath) || (h.parsed && !isStale(h, host, boot, why))) {
            // An interrupted run of this host closing its video: gone within seconds.
            if (h.parsed && h.ending && h.host == host && Clock::now() < waitUntil) {
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
                --attempt;  // waiting is not a change of hands
                continue;
            }
            throw UsageError(path + ": another render is writing it (pid " + std::to_string(h.pid) + " on " + h.host + " since " +
                             utcTime(h.since) + "); if no such render runs, remove " + lockPath);
        }
        // Stale: moved aside under a name of our own, so of two runs breaking it at once only one
        // does, and checked to be the lock judged stale (not a fresh one taken meanwhile).
        const std::string aside = unique + ".stale";
        if (::rename(lockPath.c_str(), aside.c_str()) != 0) continue;
        const std::string moved = readAll(aside, ok);
        if (ok && moved == theirs) {
            ::unlink(aside.c_str());
            if (note)
                *note = path + ": took over the lock of " +
                        (h.parsed ? "pid " + std::to_string(h.pid) + " on " + h.host + " (" + why + ")" : "an unreadable lock file");
        } else {
            if (::link(aside.c_str(), lockPath.c_str()) != 0) {
                // Its owner's lock file could not be put back; it still holds its fcntl lock.
            }
            ::unlink(aside.c_str());
        }
    }
    throw UsageError(lockPath + ": cannot take the lock: it keeps changing hands");
}

OutputLock::~OutputLock() { release(); }

OutputLock::OutputLock(OutputLock&& o) noexcept
    : lockPath_(std::exchange(o.lockPath_, {})), content_(std::exchange(o.content_, {})), fd_(std::exchange(o.fd_, -1)) {}

OutputLock& OutputLock::operator=(OutputLock&& o) noexcept {
    if (this != &o) {
        release();
        lockPath_ = std::exchange(o.lockPath_, {});
        content_ = std::exchange(o.content_, {});
        fd_ = std::exchange(o.fd_, -1);
    }
    return *this;
}

void OutputLock::markEnding() {
    if (lockPath_.empty() || fd_ < 0 || content_.empty() || content_.find(" ending") != std::string::npos) return;
    std::string ending = content_;
    if (ending.back() == '\n') ending.pop_back();
    ending += " ending\n";
    // Longer than before and the same up to the old end: a reader sees the old or the new state.
    if (::pwrite(fd_, ending.data(), ending.size(), 0) == ssize_t(ending.size())) content_ = ending;
}

void OutputLock::release() {
    if (!lockPath_.empty()) {
        bool ok = false;
        // Only our own: a lock judged stale and taken over by another run stays its.
        if (readAll(lockPath_, ok) == content_ && ok) ::unlink(lockPath_.c_str());
        lockPath_.clear();
    }
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
}

}  // namespace rf
