#pragma once
/// One writer per output. A render holds a lock on its video and on its frames directory for its
/// whole run, so a second run on the same output refuses at once instead of interleaving its
/// frames with the first one's.
///
/// The lock is a file beside the path, PATH.lock, holding "rayfarm-lock HOST PID START BOOT
/// SINCE", and " ending" once its run winds down after a signal (markEnding). It is created under a unique name and published with link(), which is atomic on
/// local file systems and on NFS (where O_EXCL is not reliable on old servers), and held with an
/// open-file-description fcntl lock besides, where the file system has one (NFS: through its lock
/// manager). A lock file whose holder is gone is stale and taken over: on this host, when the pid
/// no longer runs, runs a different program start (the pid was reused) or the host rebooted
/// since (another boot id); on any host, never while a fcntl lock is held on it. A lock of
/// another host without a fcntl lock is not taken over: that host cannot be asked. A live holder
/// whose lock says it is ending (an interrupted run closing its video) is waited for, up to
/// kEndingWaitSeconds, so that the resume command it printed works when run at once.
#include <string>

namespace rf {

/// How long a new run waits for an ending holder (markEnding) to let go before refusing.
constexpr double kEndingWaitSeconds = 10.0;

/// PATH.lock (trailing slashes of a directory dropped).
std::string lockPathFor(const std::string& path);

class OutputLock {
public:
    OutputLock() = default;
    /// Takes the lock on `path` (a file or a directory; it need not exist). Throws UsageError
    /// "PATH: another render is writing it (pid N on HOST since TIME); if no such render runs,
    /// remove PATH.lock" when
    /// a live run holds it, or "PATH.lock: cannot create the lock: REASON". A stale lock taken
    /// over is said in *note (if given).
    explicit OutputLock(const std::string& path, std::string* note = nullptr);
    ~OutputLock();
    OutputLock(OutputLock&& o) noexcept;
    OutputLock& operator=(OutputLock&& o) noexcept;
    OutputLock(const OutputLock&) = delete;
    OutputLock& operator=(const OutputLock&) = delete;

    bool held() const { return fd_ >= 0 || !lockPath_.empty(); }
    const std::string& lockPath() const { return lockPath_; }
    /// Says in the lock file that this run is ending (interrupted, closing its outputs): a run
    /// started meanwhile waits for it instead of refusing. Safe from any one thread.
    void markEnding();
    /// Removes the lock file (also done by the destructor).
    void release();

private:
    std::string lockPath_;
    std::string content_;  ///< what this process wrote into it
    int fd_ = -1;          ///< holds the fcntl lock
};

}  // namespace rf
