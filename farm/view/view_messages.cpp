#include "farm/view/view_messages.h"

#include <cstring>
#include <stdexcept>
#include <type_traits>

namespace rf::view {

// A byte copy, as encodeWorkerJob does: every rank runs the same executable.
static_assert(std::is_trivially_copyable_v<ViewJob>);

std::string encodeViewJob(const ViewJob& j) { return std::string(reinterpret_cast<const char*>(&j), sizeof j); }

ViewJob decodeViewJob(const std::string& b) {
    if (b.size() != sizeof(ViewJob)) throw std::runtime_error("malformed view job message");
    ViewJob j;
    std::memcpy(&j, b.data(), sizeof j);
    return j;
}

}  // namespace rf::view
