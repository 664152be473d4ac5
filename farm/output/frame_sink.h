#pragma once
/// Where finished frames go: the MP4 encoder, the PNG frames directory. Each is a FrameSink;
/// AsyncSink runs one on its own thread behind a bounded queue, so rank 0 keeps handing out work
/// while frames are encoded, and memory stays bounded if the encoder falls behind.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "farm/output/video_chunk.h"

namespace rf::farm {

class FrameSink {
public:
    virtual ~FrameSink() = default;
    /// Writes one frame (timeline index `frame`): width × height × 3 bytes of sRGB 8-bit RGB.
    virtual void write(int frame, const std::vector<uint8_t>& rgb) = 0;
    /// Completes the output so it is valid (MP4 trailer). Safe to call twice.
    virtual void close() = 0;
    /// Frames already in the output file, playable if the process died now; -1 for a sink that
    /// writes its file only at close (GIF) or keeps no such count. Safe from any thread.
    virtual int framesInOutput() const { return -1; }
    /// A chunk of the film encoded where it was rendered, next in order (a video joined from
    /// chunks: Mp4Sink). Other sinks take frames only: they throw std::logic_error.
    virtual void writeChunk(const EncodedChunk& chunk);
    /// A frame already compressed as PNG where it was rendered, with its SHA-256 (the PNG
    /// frames: PngSink). Other sinks throw std::logic_error.
    virtual void writePng(int frame, const std::string& png, const std::string& sha256);
    /// Whether write() does anything with this frame (a contact sheet shows a dozen): rank 0
    /// asks for the pixels of those frames only when frames are rendered elsewhere.
    virtual bool wants(int /*frame*/) const { return true; }
};

/// Hands every frame to several sinks in turn (the video and the contact sheet, the PNG and the
/// EXR frames). close() closes them all and rethrows the first error.
class TeeSink : public FrameSink {
public:
    explicit TeeSink(std::vector<std::unique_ptr<FrameSink>> sinks) : sinks_(std::move(sinks)) {}
    void write(int frame, const std::vector<uint8_t>& pixels) override;
    void close() override;
    /// The first sink's (the video, beside its contact sheet and poster).
    int framesInOutput() const override { return sinks_.empty() ? -1 : sinks_[0]->framesInOutput(); }
    void writePng(int frame, const std::string& png, const std::string& sha256) override;
    bool wants(int frame) const override;

private:
    std::vector<std::unique_ptr<FrameSink>> sinks_;
};

/// Runs a sink on its own thread. write() returns at once unless `capacity` frames are already
/// waiting; an error on the thread is rethrown by the next write() or by close(). Once the
/// thread has stopped on an error, every later write() throws that error again: nothing would
/// ever take the frames off the queue.
class AsyncSink : public FrameSink {
public:
    AsyncSink(std::unique_ptr<FrameSink> inner, int capacity);
    ~AsyncSink() override;
    void write(int frame, const std::vector<uint8_t>& rgb) override;
    void writeChunk(const EncodedChunk& chunk) override;
    void writePng(int frame, const std::string& png, const std::string& sha256) override;
    void close() override;
    int framesInOutput() const override { return inner_->framesInOutput(); }
    bool wants(int frame) const override { return inner_->wants(frame); }

    /// Seconds the thread spent inside the inner sink (write and close).
    double busySeconds() const;
    /// Frames the inner sink has completed (a chunk counts its frames).
    int framesDone() const;
    /// When the inner sink last finished work: a frame, or after close() the closing, which for
    /// an encoder is when the last frames are muxed.
    std::chrono::steady_clock::time_point lastDone() const;
    /// Frames waiting in the queue.
    int queued() const;

private:
    struct Item {
        int frame = 0;
        std::vector<uint8_t> rgb;
        std::shared_ptr<const EncodedChunk> chunk;  ///< writeChunk
        std::string png, sha256;                    ///< writePng
    };
    void push(Item item);
    void loop();
    void rethrowIfFailed();

    std::unique_ptr<FrameSink> inner_;
    int capacity_;
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<Item> queue_;
    bool closing_ = false, closed_ = false;
    std::exception_ptr error_;    ///< not yet rethrown
    std::exception_ptr stopped_;  ///< the error the thread stopped on, kept
    double busy_ = 0.0;
    int done_ = 0;
    std::chrono::steady_clock::time_point lastDone_{};
    std::thread thread_;
};

}  // namespace rf::farm
