#pragma once
/// Helpers shared by the benchmark programs.
#include <ctime>

namespace rf::bench {

/// CPU seconds used by the whole process: on a shared machine wall time counts other people's
/// work too, so the benches print both.
inline double processCpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

}  // namespace rf::bench
