#pragma once
/// A load that answers signals and says what it was doing. The engine cannot see the farm's
/// signal handlers (farm/process/interrupt.h), so the handler calls requestLoadCancel, and the
/// loaders' loops (scene files, glTF, textures, the environment's filtering, the BVH) call
/// pollLoadCancel, which then throws LoadCancelled: Ctrl-C or SIGTERM ends a load of a million
/// spheres within milliseconds, not at its end. Third-party parsers (tinygltf, nlohmann) cannot
/// poll; the farm's SignalDeadline ends the process for them.
///
/// The same steps name what a load ran out of memory doing (OutOfMemoryError), where a bare
/// std::bad_alloc said nothing.
#include <atomic>
#include <stdexcept>
#include <string>

namespace rf {

/// What the load is doing, for the messages of an interrupted or failed load ("building the
/// BVH"): set for a scope, the innermost scope wins. One load at a time per process (what the
/// commands do); the text must outlive the scope (a literal).
class LoadStep {
public:
    explicit LoadStep(const char* what) noexcept;
    ~LoadStep();
    LoadStep(const LoadStep&) = delete;
    LoadStep& operator=(const LoadStep&) = delete;

private:
    const char* what_;
    const char* outer_;
    int uncaught_;
};

/// The innermost step now ("loading" outside any); readable from any thread.
const char* currentLoadStep() noexcept;
/// For a catch block: the innermost step an exception left (its scope has closed by the time
/// the handler runs), else currentLoadStep().
const char* lastFailedStep() noexcept;

/// Asks every load of the process to stop: one atomic store, safe in a signal handler. sig is
/// the signal that asked (0 clears, for tests).
void requestLoadCancel(int sig) noexcept;
/// The signal that asked, 0 if none.
int loadCancelSignal() noexcept;

/// What pollLoadCancel throws. Deliberately not a std::exception: a loader's
/// `catch (const std::exception&)` that turns failures into input errors must let it through.
struct LoadCancelled {
    int signal = 0;
    std::string step;  ///< currentLoadStep() where the load stopped
    std::string file;  ///< the scene or model file (loadScene fills it in)
};

namespace detail {
extern std::atomic<int> gLoadCancelSignal;
[[noreturn]] void throwLoadCancelled();
}  // namespace detail

/// Throws LoadCancelled once a cancel was asked for. One relaxed load: call it from loops.
inline void pollLoadCancel() {
    if (detail::gLoadCancelSignal.load(std::memory_order_relaxed) != 0) [[unlikely]]
        detail::throwLoadCancelled();
}

/// A load that ran out of memory: "FILE: out of memory while STEP".
class OutOfMemoryError : public std::runtime_error {
public:
    OutOfMemoryError(const std::string& file, const std::string& step);
};

}  // namespace rf
