#include "farm/cluster/bench_free_work.h"

#include <chrono>
#include <cstdlib>

namespace rf::farm {

namespace {

void fillFreeWork(const TileRect& r, int frame, int channels, uint8_t* dst) {
    for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x, dst += channels) {
            dst[0] = uint8_t(x + 2 * frame);
            dst[1] = uint8_t(y + frame);
            dst[2] = uint8_t((x ^ y) + 3 * frame);
            if (channels == 4) dst[3] = 255;
        }
}

}  // namespace

RenderEngine::ItemRenderer benchFreeWorkRenderer(bool linear) {
    if (linear || std::getenv("RAYFARM_BENCH_FREE_WORK") == nullptr) return nullptr;
    return [](const WorkItem& item, int channels) {
        const auto t0 = std::chrono::steady_clock::now();
        TileResult out;
        out.item = item;
        out.layout.channels = channels;
        out.rgb.resize(out.layout.bytes(size_t(item.rect.pixels())));
        fillFreeWork(item.rect, item.frame, channels, out.rgb.data());
        out.busySeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        return out;
    };
}

}  // namespace rf::farm
