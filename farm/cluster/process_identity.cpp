#include "farm/cluster/process_identity.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include <sys/stat.h>
#include <unistd.h>

namespace rf::farm {

namespace {

/// What reading /proc/PID/stat found.
enum class StatRead { Read, NoProcess, Unreadable };

/// /proc/PID/stat's state letter and starttime. NoProcess only where the kernel says there is
/// no such process (ENOENT, ESRCH); anything else (out of file descriptors, memory, a refused
/// read, an odd line) is Unreadable, which proves nothing about the process. The command name
/// (field 2) may hold spaces and parentheses: the fields after it are counted from its last ')'.
StatRead readStat(int64_t pid, char& state, uint64_t& startTicks) {
    const std::string path = "/proc/" + std::to_string(pid) + "/stat";
    std::FILE* f = std::fopen(path.c_str(), "re");
    if (!f) return errno == ENOENT || errno == ESRCH ? StatRead::NoProcess : StatRead::Unreadable;
    char buf[1024];
    const size_t n = std::fread(buf, 1, sizeof buf - 1, f);
    std::fclose(f);
    buf[n] = '\0';
    if (n == 0) return StatRead::NoProcess;  // the process went between the open and the read
    const char* p = std::strrchr(buf, ')');
    if (!p) return StatRead::Unreadable;
    // After ") ": field 3 (state), then fields 4 to 21, then 22 (starttime).
    unsigned long long ticks = 0;
    if (std::sscanf(p + 1, " %c %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %llu", &state,
                    &ticks) != 2)
        return StatRead::Unreadable;
    startTicks = ticks;
    return StatRead::Read;
}

}  // namespace

ProcessIdentity ProcessIdentity::self() {
    ProcessIdentity id;
    id.pid = ::getpid();
    char state = 0;
    if (readStat(id.pid, state, id.startTicks) != StatRead::Read) return id;  // no /proc: pidNamespace 0, never comparable
    struct stat ns {};
    if (::stat("/proc/self/ns/pid", &ns) != 0) return id;
    if (std::FILE* f = std::fopen("/proc/sys/kernel/random/boot_id", "re")) {
        if (!std::fgets(id.boot, sizeof id.boot, f)) id.boot[0] = '\0';
        std::fclose(f);
    }
    if (id.boot[0] != '\0') id.pidNamespace = uint64_t(ns.st_ino);
    return id;
}

ProcessSeen lookAt(const ProcessIdentity& other) {
    static const ProcessIdentity me = ProcessIdentity::self();
    if (me.pidNamespace == 0 || other.pidNamespace != me.pidNamespace ||
        std::strncmp(other.boot, me.boot, sizeof me.boot) != 0)
        return ProcessSeen::Unknown;
    char state = 0;
    uint64_t ticks = 0;
    switch (readStat(other.pid, state, ticks)) {
    case StatRead::NoProcess: return ProcessSeen::Ended;
    case StatRead::Unreadable: return ProcessSeen::Unknown;
    case StatRead::Read: break;
    }
    if (ticks != other.startTicks || state == 'Z' || state == 'X') return ProcessSeen::Ended;
    return ProcessSeen::Running;
}

}  // namespace rf::farm
