#include "engine/util/load_control.h"

#include <exception>

#include "engine/util/errors.h"

namespace rf {

namespace {
std::atomic<const char*> gStep{nullptr};
/// The innermost step an exception unwound through since the last step began.
std::atomic<const char*> gFailed{nullptr};
}  // namespace

namespace detail {
std::atomic<int> gLoadCancelSignal{0};
static_assert(std::atomic<int>::is_always_lock_free, "set from signal handlers");

void throwLoadCancelled() { throw LoadCancelled{gLoadCancelSignal.load(), currentLoadStep(), ""}; }
}  // namespace detail

LoadStep::LoadStep(const char* what) noexcept : what_(what), outer_(gStep.exchange(what)), uncaught_(std::uncaught_exceptions()) {
    gFailed.store(nullptr);  // any earlier failure was handled: a new step has begun
}

LoadStep::~LoadStep() {
    // Unwinding: the first scope to close is the innermost, the one that failed.
    const char* none = nullptr;
    if (std::uncaught_exceptions() > uncaught_) gFailed.compare_exchange_strong(none, what_);
    gStep.store(outer_);
}

const char* lastFailedStep() noexcept {
    const char* f = gFailed.load();
    return f ? f : currentLoadStep();
}

const char* currentLoadStep() noexcept {
    const char* s = gStep.load();
    return s ? s : "loading";
}

void requestLoadCancel(int sig) noexcept { detail::gLoadCancelSignal.store(sig); }

int loadCancelSignal() noexcept { return detail::gLoadCancelSignal.load(); }

OutOfMemoryError::OutOfMemoryError(const std::string& file, const std::string& step)
    : std::runtime_error(printable(file) + ": out of memory while " + step) {}

}  // namespace rf
