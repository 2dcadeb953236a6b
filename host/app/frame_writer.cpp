#include "frame_writer.hpp"

#include "rank_gather.hpp"

#include <clsph/error.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <utility>

namespace clsph::app {
namespace {

std::string frame_name(std::size_t index, const char* extension) {
    char name[64];
    std::snprintf(name, sizeof name, "frame_%05zu.%s", index, extension);
    return name;
}

std::string piece_name(std::size_t index, std::size_t piece) {
    char name[64];
    std::snprintf(name, sizeof name, "frame_%05zu_p%zu.vtu", index, piece);
    return name;
}

Particles concatenate(std::vector<Particles> pieces) {
    if (pieces.size() == 1) return std::move(pieces[0]);
    Particles all;
    for (const auto& p : pieces)
        for (std::size_t i = 0; i < p.size(); ++i)
            all.push_back(p.id[i], p.type[i], p.position[i], p.velocity[i], p.density[i], p.pressure[i]);
    return all;
}

// Threads that compress one frame: half the host's cores (the other half feeds the devices or
// runs pocl's), at most 8; the pieces of a frame share them.
unsigned compress_threads(std::size_t pieces) {
    const unsigned cores = std::thread::hardware_concurrency();
    const unsigned frame = std::clamp(cores / 2, 1u, 8u);
    return std::max(1u, frame / static_cast<unsigned>(std::max<std::size_t>(pieces, 1)));
}

}  // namespace

FrameWriter::FrameWriter(std::string dir, const std::string& collection_name, FrameFormat format, FrameFilter filter,
                         std::size_t max_in_flight)
    : dir_(std::move(dir)),
      format_(format),
      filter_(std::move(filter)),
      max_in_flight_(max_in_flight ? max_in_flight : 1),
      collection_(dir_ + "/" + collection_name),
      // Across ranks the collection is rank 0's alone: another rank writing it (even empty, as a
      // new writer does) would race rank 0's renames into place.
      pvd_(!format_.ranks || rank_of(*format_.ranks) == 0 ? std::make_unique<PvdWriter>(collection_) : nullptr),
      thread_([this] { loop(); }) {}

FrameWriter::~FrameWriter() { stop(); }

void FrameWriter::resume_at(const std::vector<PvdEntry>& before, double time) {
    // Before any submit(): the writer thread has not touched the collection yet.
    std::lock_guard<std::mutex> lock(mutex_);
    const double eps = 1e-9 * std::max(1.0, std::abs(time));
    // Across ranks the collection is rank 0's to write; the others only count its frames.
    for (const auto& e : before) {
        if (e.time > time + eps) break;
        if (pvd_) pvd_->add(e.time, e.file);
        ++submitted_;
        ++written_;
        last_time_ = e.time;
    }
}

void FrameWriter::submit(double time, Particles particles) {
    std::vector<Particles> one;
    one.push_back(std::move(particles));
    submit_pieces(time, std::move(one));
}

void FrameWriter::submit_pieces(double time, std::vector<Particles> pieces) {
    // Before queuing: a thinned frame waits in less memory.
    for (auto& p : pieces) p = filter_.apply(std::move(p));
    if (format_.ranks) {  // synchronous and collective: see FrameFormat::ranks
        if (error_) std::rethrow_exception(error_);
        write_rank_piece(submitted_, time, concatenate(std::move(pieces)));
        ++submitted_;
        last_time_ = time;
        std::lock_guard<std::mutex> lock(mutex_);
        ++written_;
        return;
    }
    if (!format_.pieces && pieces.size() != 1) {
        Particles all = concatenate(std::move(pieces));
        pieces.clear();
        pieces.push_back(std::move(all));
    }
    std::unique_lock<std::mutex> lock(mutex_);
    // Frames in flight: queued plus the one being written.
    changed_.wait(lock, [&] { return error_ || queue_.size() + (busy_ ? 1 : 0) < max_in_flight_; });
    if (error_) std::rethrow_exception(error_);
    queue_.push_back(Frame{submitted_++, time, std::move(pieces)});
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
    if (format_.pieces) return write_pieces(frame);
    const std::string vtu = frame_name(frame.index, "vtu");
    write_vtu(dir_ + "/" + vtu, frame.pieces[0], filter_.fields, VtuFormat{format_.compress, compress_threads(1)});
    if (format_.csv) write_csv(dir_ + "/" + frame_name(frame.index, "csv"), frame.pieces[0], filter_.fields);
    // The collection names a frame only once its file is complete, so ParaView (which may already
    // have the .pvd open) never follows it to a missing file.
    pvd_->add(frame.time, vtu);
}

void FrameWriter::write_pieces(const Frame& frame) {
    const std::size_t n = frame.pieces.size();
    std::vector<std::string> names(n);
    std::vector<std::exception_ptr> errors(n);
    const VtuFormat vtu{format_.compress, compress_threads(n)};
    {
        std::vector<std::thread> threads;
        for (std::size_t k = 0; k < n; ++k) {
            names[k] = piece_name(frame.index, k);
            threads.emplace_back([&, k] {
                try {
                    write_vtu(dir_ + "/" + names[k], frame.pieces[k], filter_.fields, vtu);
                } catch (...) {
                    errors[k] = std::current_exception();
                }
            });
        }
        for (auto& t : threads) t.join();
    }
    for (const auto& e : errors)
        if (e) std::rethrow_exception(e);
    if (format_.csv) write_csv(dir_ + "/" + frame_name(frame.index, "csv"), concatenate(frame.pieces), filter_.fields);
    // The index once every piece is complete, the collection once the index is.
    const std::string index = frame_name(frame.index, "pvtu");
    write_pvtu(dir_ + "/" + index, names, filter_.fields);
    pvd_->add(frame.time, index);
}

void FrameWriter::write_rank_piece(std::size_t index, double time, const Particles& mine) {
    Ranks& ranks = *format_.ranks;
    const int rank = rank_of(ranks);
    std::string failure;
    try {
        write_vtu(dir_ + "/" + piece_name(index, static_cast<std::size_t>(rank)), mine, filter_.fields,
                  VtuFormat{format_.compress, compress_threads(1)});
    } catch (const std::exception& e) {
        failure = e.what();
    }
    // Every rank learns whether any failed (a full disk on one rank ends the run on all of them).
    auto any_failed = [&] {
        const auto failures = gather_text(ranks, failure);
        for (std::size_t r = 0; r < failures.size(); ++r)
            if (!failures[r].empty()) throw Error("rank " + std::to_string(r) + ": " + failures[r]);
    };
    any_failed();
    if (format_.csv) {  // the whole frame, gathered to rank 0 in slab order: one process's CSV
        const Particles all = gather_particles_to_rank0(ranks, mine);
        if (rank == 0) try {
                write_csv(dir_ + "/" + frame_name(index, "csv"), all, filter_.fields);
            } catch (const std::exception& e) {
                failure = e.what();
            }
        any_failed();
    }
    if (rank != 0) return;
    std::vector<std::string> names;
    for (int r = 0; r < ranks_in(ranks); ++r) names.push_back(piece_name(index, static_cast<std::size_t>(r)));
    const std::string pvtu = frame_name(index, "pvtu");
    write_pvtu(dir_ + "/" + pvtu, names, filter_.fields);
    pvd_->add(time, pvtu);
}

}  // namespace clsph::app
