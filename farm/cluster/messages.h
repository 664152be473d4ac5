#pragma once
/// Every message between rank 0 (the master) and the workers: the tags, the payloads and their
/// byte encoding. Per frame only work items (frame index, tile rectangle) go out and 8-bit
/// pixels come back; the scene itself travels once, by broadcast (scene_broadcast.h).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/geometry/camera.h"
#include "farm/output/pixel_layout.h"
#include "engine/integrators/render.h"
#include "engine/util/stats.h"

namespace rf::farm {

/// MPI tags. Workers talk to rank 0, and in pixel mode with chunked encoding also send their
/// tiles to the rank that assembles the tile's chunk (kTagTile).
enum Tag : int {
    kTagWork = 11,       ///< master → worker: WorkItem
    kTagResult = 12,     ///< worker → master: TileResult (header, then RGB8 pixels)
    kTagHeartbeat = 13,  ///< worker → master: Heartbeat, every kHeartbeatSeconds and on a signal
    kTagError = 14,      ///< worker → master: text; the worker stops after sending it
    kTagStop = 15,       ///< master → worker: no more work, leave (no payload)
    kTagAlive = 16,      ///< master → worker: rank 0 still runs (no payload), every kMasterBeatSeconds
    /// master → worker: ViewSpec, the camera and picture of an interactive epoch (a viewer's
    /// session through runFarm): work of any other epoch is stale and dropped, the item being
    /// rendered included
    kTagView = 17,
    /// worker → master: ChunkFrame, one frame of a chunk done (its PNG when frames are kept)
    kTagChunkFrame = 19,
    /// worker → master: the chunk's WorkItem, then its EncodedChunk (video_chunk.h)
    kTagChunkDone = 20,
    /// rayfarm view, window → rank: the timeline JSON to pose the scene as loaded with from now
    /// on (the window's camera keys changed); "" for none
    kTagViewTimeline = 23,
    /// master → the rank that assembles a chunk (chunked encoding): ChunkOrder; the chunk's
    /// frames, or their tiles, come from the rendering ranks (kTagTile; its own stay with it),
    /// and the rank encodes the chunk
    kTagChunkAssemble = 21,
    /// rendering rank → assembling rank: TileResult, a frame or a tile of one the receiver assembles
    kTagTile = 22,
    /// rendering rank → master: the TileResult's header alone (no pixels): the tile went to its
    /// assembling rank; frees the credit and carries the stats
    kTagTileDone = 24,
};

/// kTagStop's payload when a worker was lost during the run: the others leave without
/// MPI_Finalize, which would wait for the lost one.
inline constexpr const char* kStopAfterLoss = "lost";

/// How often a worker says it is alive, even while its threads render a long frame.
inline constexpr double kHeartbeatSeconds = 0.1;
/// How often rank 0 tells each worker it is alive, so a worker can notice a silent master.
inline constexpr double kMasterBeatSeconds = 0.5;

/// One unit of work: a rectangle of one frame (the whole frame in frame mode).
struct WorkItem {
    int32_t frame = 0;
    TileRect rect;
    /// The run or interactive pass it belongs to (newEpoch()): rank 0 drops results of any
    /// other, late ones of a cancelled run included. An epoch a ViewSpec names renders as that
    /// says; any other (0 too) is a frame of the job, through the timeline's camera.
    uint64_t epoch = 0;
    /// A chunk of the film (frame mode with chunked encoding): its number, and `frames` whole
    /// frames from `frame` on. -1: a single item (a frame, or a tile of one).
    int32_t chunk = -1;
    int32_t frames = 1;
    /// A tile of pixel mode with chunked encoding: the rank that assembles its frame and encodes
    /// its chunk, where the tile's pixels go (kTagTile) instead of to rank 0. -1: to rank 0.
    int32_t assembler = -1;
};

/// An interactive epoch: every work item stamped with it renders `frame` through `camera` (or
/// the timeline's camera at `frame`) at width × height and spp, the rest of the job's settings
/// unchanged. Each camera change or refinement pass is a new epoch; epochs are never reused.
struct ViewSpec {
    uint64_t epoch = 0;
    int32_t frame = 0;
    int32_t followTimeline = 0;  ///< 1: the timeline's camera at frame, not `camera`
    int32_t spp = 1, width = 1, height = 1;
    Camera camera;
};

/// A rendered work item: rect.pixels() pixels in `layout`.
struct TileResult {
    WorkItem item;
    double busySeconds = 0.0;  ///< wall time the worker's threads spent on it
    RayStats rays;
    PixelLayout layout;
    std::vector<uint8_t> rgb;  ///< layout.bytes(rect.pixels()) bytes
};

/// A worker's sign of life. signalled: the worker received SIGINT/SIGTERM (mpirun forwards
/// Ctrl-C as SIGTERM to every rank) and renders nothing more. building: it is still building its
/// scene (build_beats.h), busy and alive.
struct Heartbeat {
    int32_t currentFrame = -1;  ///< frame being rendered, -1 when idle
    int32_t signalled = 0;
    int32_t building = 0;
    int32_t threads = 0;  ///< the rank's render threads (0: not said): rank 0 sizes its credits by them
};

/// A chunk for one rank to assemble from the frames rendered for it (all but the kept ones)
/// and encode.
struct ChunkOrder {
    WorkItem item;                 ///< chunk, its first frame and frame count
    int32_t sendPngs = 0;          ///< 1: send each rendered frame back as PNG (frames are kept)
    /// Frames of the chunk kept from an earlier run (--resume): their PNG bytes, read back from
    /// rank 0's frames directory, so that only the missing frames are rendered.
    std::vector<std::pair<int32_t, std::string>> kept;
    /// Frames whose pixels rank 0 needs (the contact sheet's, the poster's).
    std::vector<int32_t> rawWanted;
};

/// One frame of a chunk done on its rank: for progress, and its PNG (kept
/// frames) or pixels (contact sheet) when asked for.
struct ChunkFrame {
    WorkItem item;              ///< the chunk's
    int32_t frame = 0;
    int32_t wasKept = 0;        ///< 1: decoded from a kept PNG, not rendered
    std::string png, pngSha256; ///< empty unless ChunkOrder::sendPngs
    std::vector<uint8_t> pixels;  ///< the 8-bit plane, only for ChunkOrder::rawWanted frames
};

std::string encodeChunkOrder(const ChunkOrder& o);
ChunkOrder decodeChunkOrder(const std::string& bytes);
std::string encodeChunkFrame(const ChunkFrame& f);
ChunkFrame decodeChunkFrame(const std::string& bytes);
/// kTagChunkDone: the item, then the serialized EncodedChunk (kept as bytes: rank 0 parses it
/// when the chunk's turn comes).
std::string encodeChunkDone(const WorkItem& item, const std::string& chunkBytes);
WorkItem decodeChunkDone(const std::string& bytes, std::string& chunkBytes);

std::string encodeWorkItem(const WorkItem& w);
/// Throws std::runtime_error on a payload of the wrong size.
WorkItem decodeWorkItem(const std::string& bytes);

std::string encodeTileResult(const TileResult& r);
/// Throws std::runtime_error on a malformed payload (wrong pixel count).
TileResult decodeTileResult(const std::string& bytes);
/// kTagTileDone: a TileResult without its pixels (rgb is not sent and comes back empty).
std::string encodeTileDone(const TileResult& r);
TileResult decodeTileDone(const std::string& bytes);

/// A fresh epoch: unique for the life of the process (never 0), so work of an earlier run on
/// the same workers (a cancelled film, a view session) is never taken for a later one's.
uint64_t newEpoch();

std::string encodeViewSpec(const ViewSpec& v);
/// Throws std::runtime_error on a payload of the wrong size.
ViewSpec decodeViewSpec(const std::string& bytes);

std::string encodeHeartbeat(const Heartbeat& h);
Heartbeat decodeHeartbeat(const std::string& bytes);

}  // namespace rf::farm
