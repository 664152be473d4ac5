#include "view_messages.h"

#include <cstring>
#include <stdexcept>
#include <type_traits>

namespace rf::view {

namespace {
// Byte copies, as encodeWorkerJob does: every rank runs the same executable.
template <class T>
std::string bytesOf(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    return std::string(reinterpret_cast<const char*>(&v), sizeof v);
}
template <class T>
T fromBytes(const std::string& b, const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (b.size() < sizeof(T)) throw std::runtime_error(std::string("malformed ") + what + " message");
    T v;
    std::memcpy(&v, b.data(), sizeof v);
    return v;
}
}  // namespace

std::string encodeViewJob(const ViewJob& j) { return bytesOf(j); }
ViewJob decodeViewJob(const std::string& b) { return fromBytes<ViewJob>(b, "view job"); }
std::string encodeViewWork(const ViewWork& w) { return bytesOf(w); }
ViewWork decodeViewWork(const std::string& b) { return fromBytes<ViewWork>(b, "view work"); }

std::string encodeViewTile(const ViewTile& t) {
    return bytesOf(t.work) + std::string(reinterpret_cast<const char*>(t.rgb.data()), t.rgb.size());
}

ViewTile decodeViewTile(const std::string& b) {
    ViewTile t;
    t.work = fromBytes<ViewWork>(b, "view tile");
    const size_t n = size_t(std::max(0, t.work.rect.pixels())) * 3;
    if (b.size() != sizeof(ViewWork) + n) throw std::runtime_error("malformed view tile message (pixel count)");
    t.rgb.assign(b.begin() + sizeof(ViewWork), b.end());
    return t;
}

}  // namespace rf::view
