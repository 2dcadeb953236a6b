// Frames written in the background: the run loop downloads particles (a device read) and hands the
// host copy over; a writer thread encodes VTU (and CSV) and updates the .pvd while the devices go
// on stepping. At most `max_in_flight` frames wait, which bounds memory when the disk is slower
// than the simulation (the run loop then waits in submit()). With --compress the writer compresses
// with several threads; with --pieces a frame is one VTU per device, written by one thread each,
// and a .pvtu index that the .pvd names.
#pragma once
#include <clsph/io.hpp>
#include <clsph/particles.hpp>
#include <clsph/ranks.hpp>

#include "frame_filter.hpp"

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace clsph::app {

// How frames are written (clsph run --csv, --compress, --pieces).
struct FrameFormat {
    bool csv = false;       // also frame_NNNNN.csv (whole, also with pieces)
    bool compress = false;  // zlib-compressed VTU (vtkZLibDataCompressor)
    bool pieces = false;    // frame_NNNNN_pK.vtu per device and frame_NNNNN.pvtu (submit_pieces)
    // Across MPI ranks (clsph/ranks.hpp): each rank writes its particles as piece K = its rank,
    // on the calling thread; once every rank has, rank 0 writes the .pvtu and the collection
    // (and with csv the whole frame as CSV, every rank's particles gathered to it).
    // (submit() and finish() are then collective: every rank calls them in step.)
    Ranks* ranks = nullptr;
};

class FrameWriter {
public:
    // Frames go to `dir`/frame_NNNNN.vtu (and .csv); the collection to `dir`/`collection_name`.
    // `filter`: which particles each frame holds (--output-stride, --output-box), in every piece.
    FrameWriter(std::string dir, const std::string& collection_name, FrameFormat format, FrameFilter filter = {},
                std::size_t max_in_flight = 2);
    // clsph resume: the collection's frames up to `time` kept (the next frame is numbered after
    // them), the later ones dropped from it (their files are written over).
    void resume_at(const std::vector<PvdEntry>& before, double time);
    ~FrameWriter();  // stops the thread; frames still queued are written first
    FrameWriter(const FrameWriter&) = delete;
    FrameWriter& operator=(const FrameWriter&) = delete;

    // Queues frame number frames_submitted() at simulated `time`. Rethrows a writer error.
    void submit(double time, Particles particles);
    // The same as pieces, one per device (Simulation::particles_by_device): with FrameFormat::pieces
    // each is written as its own VTU; without, they are written as one frame.
    void submit_pieces(double time, std::vector<Particles> pieces);
    bool pieces() const { return format_.pieces; }
    // Rethrows the first error the writer thread met (a full disk, say), if any.
    void check();
    // Writes what is queued, stops the thread and rethrows a writer error.
    void finish();

    std::size_t frames_submitted() const { return submitted_; }
    std::size_t frames_written() const;
    double last_time() const { return last_time_; }  // of the last frame submitted
    const std::string& collection_path() const { return collection_; }
    // What a frame of n particles costs on disk (bytes), for --dry-run.
    static std::size_t vtu_bytes(std::size_t n);

private:
    struct Frame {
        std::size_t index;
        double time;
        std::vector<Particles> pieces;  // one, unless FrameFormat::pieces
    };
    void loop();
    void write(const Frame& frame);
    void write_pieces(const Frame& frame);
    void write_rank_piece(std::size_t index, double time, const Particles& mine);
    void stop();

    std::string dir_;
    FrameFormat format_;
    FrameFilter filter_;
    std::size_t max_in_flight_;
    std::string collection_;
    std::unique_ptr<PvdWriter> pvd_;  // used by the writer thread only, once started; across ranks rank 0's only
    std::size_t submitted_ = 0;
    double last_time_ = -1.0;

    mutable std::mutex mutex_;
    std::condition_variable changed_;
    std::deque<Frame> queue_;
    std::size_t written_ = 0;
    bool busy_ = false;       // the thread is writing a frame it has taken off the queue
    bool closing_ = false;
    std::exception_ptr error_;
    std::thread thread_;      // last: starts after everything above exists
};

}  // namespace clsph::app
