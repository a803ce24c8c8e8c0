#include "processors/fitter/node/fit_worker.hpp"

#include <malloc.h>

#include <algorithm>
#include <exception>

namespace gyrocal::fitter::node {

FitWorker::FitWorker(Runner run) : run_(std::move(run)), thread_([this] { Loop(); }) {}

FitWorker::~FitWorker() {
    {
        std::lock_guard<std::mutex> lock(mu_);
        stop_ = true;
        jobs_.clear();
    }
    wake_.notify_all();
    thread_.join();
}

void FitWorker::Submit(std::vector<FitJob> jobs) {
    if (jobs.empty()) return;
    {
        std::lock_guard<std::mutex> lock(mu_);
        for (FitJob& j : jobs) {
            // A refit still waiting for the worker is superseded by a newer job of its unit
            // (newer bins; a final job supersedes it too): the queue holds at most one job per
            // unit and run, so a fitter slower than the data skips refits instead of falling
            // further behind (and holding ever more snapshots) until the final set comes late.
            const auto queued = std::find_if(jobs_.begin(), jobs_.end(), [&](const FitJob& q) {
                return !q.is_final && q.sensor_id == j.sensor_id && q.run_id == j.run_id;
            });
            if (queued != jobs_.end()) {
                *queued = std::move(j);
                ++superseded_;
            } else {
                jobs_.push_back(std::move(j));
            }
        }
    }
    wake_.notify_one();
}

std::vector<RampFitResult> FitWorker::Take() {
    std::lock_guard<std::mutex> lock(mu_);
    std::vector<RampFitResult> out;
    out.swap(done_);
    return out;
}

size_t FitWorker::outstanding() const {
    std::lock_guard<std::mutex> lock(mu_);
    return jobs_.size() + running_ + done_.size();
}

int64_t FitWorker::superseded() const {
    std::lock_guard<std::mutex> lock(mu_);
    return superseded_;
}

bool FitWorker::WaitIdle(std::chrono::milliseconds limit) {
    std::unique_lock<std::mutex> lock(mu_);
    return idle_.wait_for(lock, limit, [this] { return jobs_.empty() && running_ == 0; });
}

void FitWorker::Loop() {
    std::unique_lock<std::mutex> lock(mu_);
    while (true) {
        wake_.wait(lock, [this] { return stop_ || !jobs_.empty(); });
        if (stop_) return;
        FitJob job = std::move(jobs_.front());
        jobs_.pop_front();
        ++running_;
        lock.unlock();
        const auto t0 = std::chrono::steady_clock::now();
        RampFitResult r;
        try {
            r = run_(job);
        } catch (const std::exception& e) {
            r.sensor_id = job.sensor_id;
            r.report.sensor_id = job.sensor_id;
            r.report.run_id = job.run_id;
            r.report.utime = job.utime;
            r.report.coeff_set_id = -1;
            r.report.is_final = job.is_final;
            r.report.status = "none";
            r.report.reason = std::string("internal error in the fit: ") + e.what();
        }
        r.fit_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        job = FitJob{};
        // A fit's working memory (~14 kB per bin of the unit: 0.12 GB at a day of 10 s bins) is
        // freed, but glibc keeps freed heap pages in its arenas: without this the process's
        // resident size stays at its largest fit's, and grows with the run (the day run: +618 MB).
        malloc_trim(0);
        lock.lock();
        --running_;
        done_.push_back(std::move(r));
        if (jobs_.empty() && running_ == 0) idle_.notify_all();
    }
}

}  // namespace gyrocal::fitter::node
