#pragma once
/// Seeing another rank's process die. A worker whose rank 0 runs under the same kernel (the same
/// machine, or network namespaces on it) can look at rank 0's process itself: when it has ended,
/// rank 0 is dead, not cut off, and the worker need not wait out a silence. A rank on another
/// machine (or in another PID namespace) cannot be seen; then only its silence tells.
#include <cstdint>

namespace rf::farm {

/// Who a process is, in terms another process on the same kernel can check: its PID, when it
/// started (so a PID used again is not taken for it), the kernel's boot and the PID namespace.
struct ProcessIdentity {
    int64_t pid = 0;
    uint64_t startTicks = 0;   ///< /proc/PID/stat's starttime: clock ticks after boot
    uint64_t pidNamespace = 0; ///< inode of /proc/self/ns/pid
    char boot[40] = {};        ///< /proc/sys/kernel/random/boot_id

    /// This process.
    static ProcessIdentity self();
};

enum class ProcessSeen {
    Unknown,  ///< another kernel or PID namespace (or no /proc): nothing can be told
    Running,  ///< the process is there (running, sleeping or stopped)
    Ended,    ///< it is gone, a zombie, or its PID now holds another process
};

/// What this process can see of `other`.
ProcessSeen lookAt(const ProcessIdentity& other);

}  // namespace rf::farm
