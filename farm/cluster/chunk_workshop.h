#pragma once
/// A rank's side of frame mode with chunked encoding: it takes a chunk (ChunkOrder), renders
/// the chunk's frames on the rank's RenderEngine, and on a thread of its own compresses each
/// frame to PNG (when frames are kept) and encodes the chunk with a fresh encoder
/// (chunk_encoder.h). What goes back to rank 0 is one small message a frame (its PNG, if kept)
/// and the encoded chunk, never the raw pixels. Workers and rank 0 (when it renders) use it
/// alike; the rank's main thread stays free for messages.
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
    ChunkWorkshop(RenderEngine& engine, ChunkVideoSpec spec);
    ~ChunkWorkshop();
    ChunkWorkshop(const ChunkWorkshop&) = delete;
    ChunkWorkshop& operator=(const ChunkWorkshop&) = delete;

    /// Queues a chunk behind those already here.
    void submit(ChunkOrder order);
    /// Moves work along and returns the messages for rank 0 ready since the last call, as
    /// (tag, payload): the engine's results are taken (waiting up to waitSeconds for one), frames
    /// of the chunks go to the engine a few at a time (so at most a few frames wait in memory
    /// for the encoder), and results of single items (not chunks) pass through as kTagResult.
    std::vector<std::pair<int, std::string>> poll(double waitSeconds);
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
    };
    void feedEngine();
    void queueReady();
    void encoderLoop();
    void encodeTask(Task& t);
    void post(int tag, std::string bytes);

    struct EncoderState;
    RenderEngine& engine_;
    ChunkVideoSpec spec_;
    std::unique_ptr<EncoderState> enc_;

    // The main thread's: frames of the submitted chunks in order, and rendered results waiting
    // for their turn.
    std::deque<Pending> pending_;
    std::deque<TileResult> rendered_;
    int inEngine_ = 0;  ///< frames submitted to the engine and not yet taken back
    int chunksOut_ = 0;

    // Shared with the encoder thread.
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<Task> tasks_;
    std::vector<std::pair<int, std::string>> outbox_;
    bool working_ = false;  ///< the encoder thread has a frame in hand
    bool stop_ = false;
    std::string error_;
    std::thread thread_;
};

}  // namespace rf::farm
