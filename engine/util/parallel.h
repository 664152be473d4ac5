#pragma once
/// Work spread over threads: the engine's one thread pool pattern (tiles, BVH builds, caches).
#include <functional>

namespace rf {

/// Runs job(i) for i in [0, n) on `threads` threads (0: all cores), handing out indices
/// dynamically. job must be thread-safe; exceptions are rethrown on the calling thread.
void parallelFor(int n, int threads, const std::function<void(int index, int thread)>& job);

/// Number of hardware threads (at least 1).
int hardwareThreads();

}  // namespace rf
