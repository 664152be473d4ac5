#include "farm/cluster/process_identity.h"

#include <cstdio>
#include <cstring>
#include <string>

#include <sys/stat.h>
#include <unistd.h>

namespace rf::farm {

namespace {

/// /proc/PID/stat's state letter and starttime; false when the file cannot be read (no such
/// process). The command name (field 2) may hold spaces and parentheses: the fields after it
/// are counted from its last ')'.
bool readStat(int64_t pid, char& state, uint64_t& startTicks) {
    const std::string path = "/proc/" + std::to_string(pid) + "/stat";
    std::FILE* f = std::fopen(path.c_str(), "re");
    if (!f) return false;
    char buf[1024];
    const size_t n = std::fread(buf, 1, sizeof buf - 1, f);
    std::fclose(f);
    buf[n] = '\0';
    const char* p = std::strrchr(buf, ')');
    if (!p) return false;
    // After ") ": field 3 (state), then fields 4 to 21, then 22 (starttime).
    unsigned long long ticks = 0;
    if (std::sscanf(p + 1, " %c %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %*s %llu", &state,
                    &ticks) != 2)
        return false;
    startTicks = ticks;
    return true;
}

}  // namespace

ProcessIdentity ProcessIdentity::self() {
    ProcessIdentity id;
    id.pid = ::getpid();
    char state = 0;
    if (!readStat(id.pid, state, id.startTicks)) return id;  // no /proc: pidNamespace 0, never comparable
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
    if (!readStat(other.pid, state, ticks)) return ProcessSeen::Ended;
    if (ticks != other.startTicks || state == 'Z' || state == 'X') return ProcessSeen::Ended;
    return ProcessSeen::Running;
}

}  // namespace rf::farm
