#include "engine/util/parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace rf {

int hardwareThreads() { return std::max(1u, std::thread::hardware_concurrency()); }

void parallelFor(int n, int threads, const std::function<void(int, int)>& job) {
    if (threads <= 0) threads = hardwareThreads();
    threads = std::max(1, std::min(threads, n));
    std::atomic<int> next{0};
    std::exception_ptr error;
    std::mutex errorMutex;
    auto worker = [&](int t) {
        for (;;) {
            const int i = next.fetch_add(1);
            if (i >= n) return;
            try {
                job(i, t);
            } catch (...) {
                std::lock_guard<std::mutex> lock(errorMutex);
                if (!error) error = std::current_exception();
                next = n;
                return;
            }
        }
    };
    if (threads == 1) {
        worker(0);
    } else {
        std::vector<std::thread> pool;
        for (int t = 1; t < threads; ++t) pool.emplace_back(worker, t);
        worker(0);
        for (auto& th : pool) th.join();
    }
    if (error) std::rethrow_exception(error);
}

}  // namespace rf
