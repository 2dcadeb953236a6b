#include "frame_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace clsph::app {
namespace {

std::string frame_name(std::size_t index, const char* extension) {
    char name[64];
    std::snprintf(name, sizeof name, "frame_%05zu.%s", index, extension);
    return name;
}

}  // namespace

FrameWriter::FrameWriter(std::string dir, const std::string& collection_name, bool csv, FrameFilter filter,
                         std::size_t max_in_flight)
    : dir_(std::move(dir)),
      csv_(csv),
      filter_(std::move(filter)),
      max_in_flight_(max_in_flight ? max_in_flight : 1),
      pvd_(dir_ + "/" + collection_name),
      thread_([this] { loop(); }) {}

FrameWriter::~FrameWriter() { stop(); }

void FrameWriter::resume_at(const std::vector<PvdEntry>& before, double time) {
    // Before any submit(): the writer thread has not touched the collection yet.
    std::lock_guard<std::mutex> lock(mutex_);
    const double eps = 1e-9 * std::max(1.0, std::abs(time));
    for (const auto& e : before) {
        if (e.time > time + eps) break;
        pvd_.add(e.time, e.file);
        ++submitted_;
        ++written_;
        last_time_ = e.time;
    }
}

void FrameWriter::submit(double time, Particles particles) {
    particles = filter_.apply(std::move(particles));  // before queuing: a thinned frame waits in less memory
    std::unique_lock<std::mutex> lock(mutex_);
    // Frames in flight: queued plus the one being written.
    changed_.wait(lock, [&] { return error_ || queue_.size() + (busy_ ? 1 : 0) < max_in_flight_; });
    if (error_) std::rethrow_exception(error_);
    queue_.push_back(Frame{submitted_++, time, std::move(particles)});
    last_time_ = time;
    changed_.notify_all();
}

void FrameWriter::check() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (error_) std::rethrow_exception(error_);
}

void FrameWriter::finish() {
    stop();
    check();
}

std::size_t FrameWriter::frames_written() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return written_;
}

std::size_t FrameWriter::vtu_bytes(std::size_t n) {
    // Per particle: id 4, type 1, velocity 12, density 4, pressure 4, position 24, and the vertex
    // cells (connectivity 4, offset 4, type 1); plus ~1.5 KiB of XML and block headers.
    return 58 * n + 1536;
}

void FrameWriter::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        closing_ = true;
    }
    changed_.notify_all();
    if (thread_.joinable()) thread_.join();
}

void FrameWriter::loop() {
    for (;;) {
        Frame frame{};
        {
            std::unique_lock<std::mutex> lock(mutex_);
            changed_.wait(lock, [&] { return closing_ || !queue_.empty(); });
            if (queue_.empty() || error_) return;  // closing, and nothing (more) to write
            frame = std::move(queue_.front());
            queue_.pop_front();
            busy_ = true;
        }
        std::exception_ptr error;
        try {
            write(frame);
        } catch (...) {
            error = std::current_exception();
        }
        {
            std::lock_guard<std::mutex> lock(mutex_);
            busy_ = false;
            if (error) {
                error_ = error;
                queue_.clear();  // the run ends; nothing after a failed frame is written
            } else {
                ++written_;
            }
        }
        changed_.notify_all();
    }
}

void FrameWriter::write(const Frame& frame) {
    const std::string vtu = frame_name(frame.index, "vtu");
    write_vtu(dir_ + "/" + vtu, frame.particles, filter_.fields);
    if (csv_) write_csv(dir_ + "/" + frame_name(frame.index, "csv"), frame.particles, filter_.fields);
    // The collection names a frame only once its file is complete, so ParaView (which may already
    // have the .pvd open) never follows it to a missing file.
    pvd_.add(frame.time, vtu);
}

}  // namespace clsph::app
