#pragma once
// Fits off the receive path: one worker thread runs the fits (RampFitter::Run, seconds for a long
// run) that the node's handlers only hand it, so that receiving and binning never wait for a fit.
//
// Threads: the node's thread calls Submit() (from a handler) and Take() (between dispatches, in
// RunLoop's hook) and publishes what Take() returns: the bus is only ever touched by that thread.
// The worker runs the jobs in submission order, but a queued refit (not final, not under way)
// is replaced by a newer job of the same unit and run: at most one job per unit waits, so a fit
// slower than the data skips refits (counted: superseded()) and the final set is never queued
// behind a backlog. A job is self-contained (a snapshot of its bins
// and the fitter's const options), so nothing is shared with the handlers but the two queues,
// each behind the mutex. The destructor lets the job under way finish and drops the rest (the
// process is stopping: the launcher waits for the final sets before it stops the fitter).
// A fit that throws becomes a report "none" with the reason, never an escaped exception.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "processors/fitter/ramp_fitter.hpp"

namespace gyrocal::fitter::node {

class FitWorker {
public:
    using Runner = std::function<RampFitResult(const FitJob&)>;
    explicit FitWorker(Runner run);
    ~FitWorker();
    FitWorker(const FitWorker&) = delete;
    FitWorker& operator=(const FitWorker&) = delete;

    void Submit(std::vector<FitJob> jobs);
    // Results done so far, in submission order (each with fit_wall_s set).
    std::vector<RampFitResult> Take();
    size_t outstanding() const;  // submitted and not yet taken
    int64_t superseded() const;  // queued refits replaced by a newer job of their unit
    // Blocks until every submitted job is done or `limit` passes (tests, benchmarks).
    bool WaitIdle(std::chrono::milliseconds limit);

private:
    void Loop();

    Runner run_;
    mutable std::mutex mu_;
    std::condition_variable wake_, idle_;
    std::deque<FitJob> jobs_;
    std::vector<RampFitResult> done_;
    size_t running_ = 0;
    int64_t superseded_ = 0;
    bool stop_ = false;
    std::thread thread_;  // last: started once the rest is initialised
};

}  // namespace gyrocal::fitter::node
