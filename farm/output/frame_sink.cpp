#include "farm/output/frame_sink.h"

#include <stdexcept>

namespace rf::farm {

void FrameSink::writeChunk(const EncodedChunk&) { throw std::logic_error("this output takes frames, not encoded chunks"); }

void FrameSink::writePng(int, const std::string&, const std::string&) {
    throw std::logic_error("this output takes frames, not PNG files");
}

void TeeSink::writePng(int frame, const std::string& png, const std::string& sha256) {
    for (auto& s : sinks_) s->writePng(frame, png, sha256);
}

bool TeeSink::wants(int frame) const {
    for (const auto& s : sinks_)
        if (s->wants(frame)) return true;
    return false;
}

void TeeSink::write(int frame, const std::vector<uint8_t>& pixels) {
    for (auto& s : sinks_) s->write(frame, pixels);
}

void TeeSink::close() {
    std::exception_ptr first;
    for (auto& s : sinks_) {
        try {
            s->close();
        } catch (...) {
            if (!first) first = std::current_exception();
        }
    }
    if (first) std::rethrow_exception(first);
}

AsyncSink::AsyncSink(std::unique_ptr<FrameSink> inner, int capacity)
    : inner_(std::move(inner)), capacity_(std::max(1, capacity)) {
    thread_ = std::thread([this] { loop(); });
}

AsyncSink::~AsyncSink() {
    try {
        close();
    } catch (...) {
        // The owner saw (or chose to ignore) the error through close(); a destructor must not throw.
    }
}

void AsyncSink::rethrowIfFailed() {
    if (error_) {
        std::exception_ptr e = error_;
        error_ = nullptr;
        std::rethrow_exception(e);
    }
}

void AsyncSink::write(int frame, const std::vector<uint8_t>& rgb) {
    Item item;
    item.frame = frame;
    item.rgb = rgb;
    push(std::move(item));
}

void AsyncSink::writeChunk(const EncodedChunk& chunk) {
    Item item;
    item.frame = -1;
    item.chunk = std::make_shared<const EncodedChunk>(chunk);
    push(std::move(item));
}

void AsyncSink::writePng(int frame, const std::string& png, const std::string& sha256) {
    Item item;
    item.frame = frame;
    item.png = png;
    item.sha256 = sha256;
    push(std::move(item));
}

void AsyncSink::push(Item item) {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait(lock, [&] { return int(queue_.size()) < capacity_ || stopped_ || closing_; });
    rethrowIfFailed();
    if (stopped_) std::rethrow_exception(stopped_);
    if (closing_) return;
    queue_.push_back(std::move(item));
    cv_.notify_all();
}

void AsyncSink::close() {
    {
        std::unique_lock<std::mutex> lock(mutex_);
        if (!closing_) {
            closing_ = true;
            cv_.notify_all();
        }
    }
    if (thread_.joinable()) thread_.join();
    std::lock_guard<std::mutex> lock(mutex_);
    rethrowIfFailed();
}

void AsyncSink::loop() {
    for (;;) {
        Item item;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            cv_.wait(lock, [&] { return !queue_.empty() || closing_; });
            if (queue_.empty()) break;  // closing and drained
            item = std::move(queue_.front());
            queue_.pop_front();
            cv_.notify_all();
        }
        const auto t0 = std::chrono::steady_clock::now();
        try {
            if (item.chunk) inner_->writeChunk(*item.chunk);
            else if (!item.png.empty()) inner_->writePng(item.frame, item.png, item.sha256);
            else inner_->write(item.frame, item.rgb);
        } catch (...) {
            std::lock_guard<std::mutex> lock(mutex_);
            error_ = stopped_ = std::current_exception();
            queue_.clear();
            cv_.notify_all();
            break;
        }
        const auto t1 = std::chrono::steady_clock::now();
        std::lock_guard<std::mutex> lock(mutex_);
        busy_ += std::chrono::duration<double>(t1 - t0).count();
        done_ += item.chunk ? item.chunk->frames : 1;
        lastDone_ = t1;
    }
    const auto t0 = std::chrono::steady_clock::now();
    try {
        inner_->close();
    } catch (...) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!error_) error_ = std::current_exception();
    }
    const auto t1 = std::chrono::steady_clock::now();
    std::lock_guard<std::mutex> lock(mutex_);
    busy_ += std::chrono::duration<double>(t1 - t0).count();
    lastDone_ = t1;  // an encoder holds frames back until it is closed: they are muxed only now
    closed_ = true;
}

double AsyncSink::busySeconds() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return busy_;
}

int AsyncSink::framesDone() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return done_;
}

std::chrono::steady_clock::time_point AsyncSink::lastDone() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return lastDone_;
}

int AsyncSink::queued() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return int(queue_.size());
}

}  // namespace rf::farm
