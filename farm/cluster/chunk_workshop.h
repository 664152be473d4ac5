#pragma once
/// A rank's side of frame mode with chunked encoding: it takes a chunk (ChunkOrder), renders
/// the chunk's frames on the rank's RenderEngine, and on a thread of its own compresses each
/// frame to PNG (when frames are kept) and encodes the chunk with a fresh encoder
/// (chunk_encoder.h). What goes back to rank 0 is one small message a frame (its PNG, if kept)
/// and the encoded chunk, never the raw pixels. Workers and rank 0 (when it renders) use it
/// alike; the rank's main thread stays free for messages.
///
/// In pixel mode with chunked encoding a rank also assembles chunks (submitAssembly): the
/// chunk's frames are not rendered here but put together from the tiles every rendering rank
/// sends (addTile), then compressed and encoded the same way. The engine's results for tiles of
/// such frames (WorkItem::assembler) go to their assembling rank, and a note of them to rank 0.
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "messages.h"
#include "video_options.h"
#include "render_engine.h"

namespace rf::farm {

/// What every rank needs to encode the job's chunks as rank 0 would.
struct ChunkVideoSpec {
    std::string path;  ///< the output's name: its extension picks the format
    int width = 0, height = 0;
    Mp4Options options;  ///< options.chunkFrames is K, options.channels the frames' 8-bit plane
};

/// The spec as bytes for the job broadcast, and back (throws std::runtime_error when malformed).
std::string encodeChunkVideoSpec(const ChunkVideoSpec& s);
ChunkVideoSpec decodeChunkVideoSpec(const std::string& bytes);

class ChunkWorkshop {
public:
    /// A message for another rank: rank 0 (dest 0), or a tile's assembling rank.
    struct Outgoing {
        int dest = 0;
        int tag = 0;
        std::string bytes;
    };

    /// rank: this rank's number (a tile it assembles itself is not sent to itself).
    ChunkWorkshop(RenderEngine& engine, ChunkVideoSpec spec, int rank = 0);
    ~ChunkWorkshop();
    ChunkWorkshop(const ChunkWorkshop&) = delete;
    ChunkWorkshop& operator=(const ChunkWorkshop&) = delete;

    /// Queues a chunk behind those already here, to render and encode.
    void submit(ChunkOrder order);
    /// Queues a chunk to assemble from tiles (addTile) and encode; its kept frames are not
    /// rendered anywhere.
    void submitAssembly(ChunkOrder order);
    /// A tile of a frame this rank assembles (its chunk's order may still be on its way: the
    /// tile waits for it). Throws std::runtime_error on a tile that does not fit the frame.
    void addTile(TileResult tile);
    /// Moves work along and returns the messages ready since the last call: the engine's
    /// results are taken (waiting up to waitSeconds for one), frames of the chunks go to the
    /// engine a few at a time (so at most a few frames wait in memory for the encoder), results
    /// of single items (not chunks) pass through to rank 0 as kTagResult, and tiles of assembled
    /// frames go to their assembling rank (kTagTile; kept here when that is this rank) with a
    /// kTagTileDone to rank 0.
    std::vector<Outgoing> poll(double waitSeconds);
    /// Chunks submitted and not yet sent back.
    int outstanding() const;
    /// The error that stopped the encoding thread, or the engine's; "" while all is well.
    std::string error() const;
    /// Drops queued chunks and frames (a signal: rank 0 closes the video without them).
    void cancel();

private:
    /// One frame on its way: rendered (result) or kept (png), in the chunk's order.
    struct Task {
        std::shared_ptr<const ChunkOrder> order;
        int frame = 0;
        bool first = false, last = false;  ///< of its chunk
        const std::string* keptPng = nullptr;  ///< into order->kept
        TileResult result;                      ///< rendered frames
    };
    struct Pending {
        std::shared_ptr<const ChunkOrder> order;
        int frame = 0;
        const std::string* keptPng = nullptr;
        bool submitted = false;  ///< to the engine (rendered frames)
        bool assembled = false;  ///< put together from tiles (submitAssembly), not rendered here
        std::vector<uint8_t> pixels;  ///< an assembled frame's plane, allocated at its first tile
        std::vector<bool> covered;    ///< its pixels a tile brought (a tile twice is an error)
        int64_t pixelsLeft = 0;       ///< of an assembled frame, still to come
    };
    void queueChunk(ChunkOrder order, bool assemble);
    /// Copies tile into its frame; false if no frame here takes it (yet).
    bool placeTile(const TileResult& tile);
    void feedEngine();
    void queueReady();
    void encoderLoop();
    void encodeTask(Task& t);
    void post(int tag, std::string bytes);

    struct EncoderState;
    RenderEngine& engine_;
    ChunkVideoSpec spec_;
    std::unique_ptr<EncoderState> enc_;

    // The main thread's: frames of the submitted chunks in order (each chunk's in its order;
    // chunks go to the encoder independently), and rendered results waiting for their turn.
    std::deque<Pending> pending_;
    std::deque<TileResult> rendered_;
    /// Tiles that came before their chunk's order (from a rank that heard of the chunk first).
    std::vector<TileResult> early_;
    int rank_ = 0;
    int inEngine_ = 0;  ///< frames submitted to the engine and not yet taken back
    int chunksOut_ = 0;

    // Shared with the encoder thread.
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<Task> tasks_;
    std::vector<Outgoing> outbox_;
    bool working_ = false;  ///< the encoder thread has a frame in hand
    bool stop_ = false;
    std::string error_;
    std::thread thread_;
};

}  // namespace rf::farm
