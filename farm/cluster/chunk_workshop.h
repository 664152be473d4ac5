#pragma once
/// A rank's side of chunked encoding. It assembles the chunks rank 0 gives it (submitAssembly,
/// a ChunkOrder) from the items rendered for them: whole frames in frame mode, tiles in pixel
/// mode, from its own engine or from other ranks (addTile). On a thread of its own it
/// compresses each frame to PNG (when frames are kept) and encodes the chunk with a fresh
/// encoder (chunk_encoder.h). What goes back to rank 0 is one small message a frame (its PNG,
/// if kept) and the encoded chunk, never the raw pixels. The engine's results for frames other
/// ranks assemble (WorkItem::assembler) go there, and a note of every result to rank 0 (its
/// credit). Workers and rank 0 (when it renders) use it alike; the rank's main thread stays
/// free for messages.
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "farm/cluster/messages.h"
#include "farm/output/video_options.h"
#include "farm/cluster/render_engine.h"

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

    /// Queues a chunk to assemble (addTile, and the engine's results for it) and encode; its
    /// kept frames are not rendered anywhere.
    void submitAssembly(ChunkOrder order);
    /// A frame, or a tile of one, this rank assembles (its chunk's order may still be on its
    /// way: it waits for it). Throws std::runtime_error on one that does not fit the frame.
    void addTile(TileResult tile);
    /// Moves work along and returns the messages ready since the last call. The engine's
    /// results are taken (waiting up to waitSeconds for one): those of single items (no chunk)
    /// pass through to rank 0 as kTagResult; those another rank assembles go there (kTagTile)
    /// with a kTagTileDone to rank 0; this rank's own are placed, with their kTagTileDone, while
    /// its encoder keeps up (so a rank that renders faster than it encodes is given no more).
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
        const std::string* keptPng = nullptr;  ///< a kept frame: nothing to assemble
        std::vector<uint8_t> pixels;  ///< the frame's plane, from its first tile on
        std::vector<uint8_t> covered; ///< 1 for each pixel a tile brought (a tile twice is an error)
        int64_t pixelsLeft = 0;       ///< still to come
    };
    /// Puts tile into its frame (a whole frame's pixels are moved, not copied); false if no
    /// frame here takes it (yet).
    bool placeTile(TileResult& tile);
    /// Whole frames queued for the encoder thread, the one in its hands included.
    int encoderBacklog() const;
    void queueReady();
    void encoderLoop();
    void encodeTask(Task& t);
    void post(int tag, std::string bytes);

    struct EncoderState;
    RenderEngine& engine_;
    ChunkVideoSpec spec_;
    std::unique_ptr<EncoderState> enc_;

    // The main thread's: frames of the submitted chunks in order (each chunk's in its order;
    // chunks go to the encoder independently).
    std::deque<Pending> pending_;
    /// The engine's results for frames assembled here, waiting for the encoder to keep up.
    std::deque<TileResult> own_;
    /// Tiles that came before their chunk's order (from a rank that heard of the chunk first).
    std::vector<TileResult> early_;
    int rank_ = 0;
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
