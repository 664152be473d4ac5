#include "farm/output/digest.h"

#include <stdexcept>

extern "C" {
#include <libavutil/hash.h>
}

namespace rf::farm {

std::string sha256Hex(std::string_view bytes) {
    AVHashContext* ctx = nullptr;
    if (av_hash_alloc(&ctx, "SHA256") < 0 || !ctx) throw std::runtime_error("this FFmpeg has no SHA-256");
    av_hash_init(ctx);
    // av_hash_update takes an int length on older FFmpeg: feed large inputs in pieces.
    for (size_t at = 0; at < bytes.size(); at += size_t(1) << 30) {
        const size_t n = std::min(bytes.size() - at, size_t(1) << 30);
        av_hash_update(ctx, reinterpret_cast<const uint8_t*>(bytes.data() + at), int(n));
    }
    char hex[2 * AV_HASH_MAX_SIZE + 1];
    av_hash_final_hex(ctx, reinterpret_cast<uint8_t*>(hex), sizeof hex);
    av_hash_freep(&ctx);
    return hex;
}

}  // namespace rf::farm
