// libFuzzer harness: what a worker or the master decodes from the wire. The first byte picks
// the decoder; the rest is the payload. Every decoder must refuse a malformed payload with
// std::runtime_error, and a decoded work item must encode back to the same bytes. Issue 32's
// payloads too: a chunk order, a chunk's frame, a chunk done and the encoded chunk itself, and
// a tile's header-only note.
#include <cstdlib>

#include "tests/fuzz/fuzz_input.h"
#include "farm/cluster/messages.h"
#include "farm/output/video_chunk.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const std::string payload = rffuzz::bytes(data + 1, size - 1);
    try {
        switch (data[0] % 7) {
        case 0:
            if (rf::farm::encodeWorkItem(rf::farm::decodeWorkItem(payload)) != payload) std::abort();
            break;
        case 1: {
            const rf::farm::TileResult r = rf::farm::decodeTileResult(payload);
            (void)r;
            break;
        }
        case 2:
            (void)rf::farm::decodeTileDone(payload);  // a tile's note to rank 0 (pixel mode's assembled chunks)
            break;
        case 3:
            (void)rf::farm::decodeChunkOrder(payload);
            break;
        case 4:
            (void)rf::farm::decodeChunkFrame(payload);
            break;
        case 5: {
            std::string chunk;
            (void)rf::farm::decodeChunkDone(payload, chunk);
            (void)rf::farm::parseChunk(chunk);
            break;
        }
        default:
            (void)rf::farm::decodeHeartbeat(payload);  // padding bytes need not survive a round trip
        }
    } catch (const std::runtime_error&) {
    }
    return 0;
}
