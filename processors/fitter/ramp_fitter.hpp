#pragma once
// The fit on EVERY still window of a run, through the analysis: the ramp fitter (gyrocal-fitter
// --mode ramp, whose sets are the run's) and the plateau mode's closed loop (the run's final set
// beside the plateau-only one).
//
// A ramp never holds a temperature, so there are no plateau means to fit; and on a plateau run
// the plateaus are some 5 % of the still data. Instead the run's samples are binned as they come
// (analysis/bins_incremental.hpp: the analysis' 10 s still bins and their model inputs, without
// keeping the samples: memory bounded by the bins, ~0.2 MB per unit-hour instead of the 14 MB of
// the raw samples), with the table's encoder, the units' power records, the chamber air and the
// rotation estimator's sensitivity points, and the analysis library does the fit
// (analysis/analyze.hpp): its model inputs (dT/dt with its time constant, heating/cooling branch:
// model/inputs.hpp, the trackers the compensators run), its forward selection of the rate,
// branch, cubic, supply and warm-up terms on held-out blocks and its held-out confirmation, its
// autocorrelation-robust coefficient covariance, its sensitivity fit on the rotation points, its
// verdict. The set published is the analysis' extended model refitted on all bins: the same
// fitter and the same selection as `gyrocal analyze`, so a term is in a set only when the data
// showed it.
//
// When: during the run every refit_interval_s of data time once min_span_s of samples are in
// (refit_during_run; the compensator and the sequencer's early stop use them), and once at the
// run's stop (the final set, with is_final reports).
// Threads: the fitter's state (binning) lives on the receiving thread; a fit is a FitJob, a
// snapshot of one unit's bins taken there (cheap: it shares the bins' closed chunks), run by
// Run(), which is const and touches nothing else, so a worker thread runs it (fit_worker.hpp)
// while the samples keep coming.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/fit_report_t.hpp"
#include "processors/analysis/analyze.hpp"
#include "processors/analysis/bins_incremental.hpp"
#include "processors/analysis/plot.hpp"
#include "processors/analysis/run_data.hpp"

namespace gyrocal::fitter {

struct RampFitterOptions {
    analysis::AnalysisOptions analysis = analysis::AnalysisOptions::Defaults();
    analysis::BuildOptions build = analysis::BuildOptions::Defaults();
    double refit_interval_s = 600.0;  // [s] data time between fits during the run
    double min_span_s = 1200.0;       // [s] of a unit's samples before its first fit in the run
    bool refit_during_run = true;     // false: the final fit only (the plateau mode's closed loop)
    // After the stop, keep the run's bins until the next run starts, so that a point arriving
    // late can make the final set again (the plateau mode's closed loop); false: drop them.
    bool keep_after_stop = false;
    std::string source = "fitter";  // coeff_set_t.source of the sets ("closed-loop": plateau mode)
    std::string method = "ramp";    // model_t.method of their models
    double width_ratio = 1.03;      // [1] branch widths tracked (bins_incremental.hpp)
    // Each unit's still bins held to at most this many (0: no limit): beyond it, neighbours
    // merge into bins twice as long (IncrementalOptions::max_cells), so the fitter's memory
    // stops growing with the run (4096: about 3 MB of bins per unit and one fit over them; a run
    // shorter than 11.4 h keeps its 10 s bins, a day is fitted on 40 s bins). The analysis
    // measures the run's noise the same at either length (processors/analysis/noise_model.hpp),
    // so the merged bins' verdict is the 10 s bins' (processors/fitter/README.md).
    int64_t max_bins_per_unit = 4096;
    // The published set carries the cubic (dT^3) when the verdict did not name it but it lowers
    // the held-out error (analysis::CarryForPrediction): the set is for prediction.
    bool carry_cubic = true;
    static RampFitterOptions Defaults() { return {}; }
    // The plateau mode's closed loop: the final set only, source "closed-loop", method "analysis".
    static RampFitterOptions ClosedLoop();
    std::string Validate() const;  // "" when valid, else the option and what is valid
};

// One unit's fit to make: its bins at a moment, and what the set will be called.
struct FitJob {
    std::string sensor_id, run_id;
    int64_t utime = 0;  // [us] of the set: the newest sample, or the stop event's (final)
    bool is_final = false;
    analysis::BinSnapshot bins;
    // Not "": the analysis runs and is published, but no set, for this reason (the plateau mode's
    // closed loop when the unit's plateau set is partial: its temperatures do not support a
    // temperature model, and a fit on every still sample of them would only extrapolate).
    std::string withhold;
};

struct RampFitResult {
    std::string sensor_id;
    std::optional<coeff_set_t> set;  // nullopt when no model could be fitted (report says why)
    fit_report_t report;
    std::optional<analysis::SensorResult> analysis;  // the analysis behind it, when one ran
    // Its residual per still bin before and after (analysis/plot.hpp's <id>_residual table).
    std::optional<plot::Table> residual;
    double fit_wall_s = 0.0;  // [s] wall time the fit took (Run leaves it 0: the worker sets it)
};

class RampFitter {
public:
    explicit RampFitter(RampFitterOptions options);  // throws std::invalid_argument on Validate()

    // The run's id (RUN_EVENT start). Samples heard before it are kept: they are the units at
    // rest at the start temperature, and the model inputs are tracked from the first sample.
    void StartRun(const std::string& run_id);
    void AddGyro(const std::string& sensor_id, const analysis::GyroSample& s);
    void AddEncoder(const motion::EncoderReading& e);
    void AddSensitivity(const std::string& sensor_id, const analysis::SensitivityInput& p);
    void AddPower(const std::string& sensor_id, const analysis::PowerRecord& p);
    void AddAir(const analysis::AirSample& a);
    void AddPlateau(const std::string& sensor_id, const analysis::PlateauInput& p);

    // Data time advanced: the fits that are due (see above); empty outside a run.
    std::vector<FitJob> DueJobs(int64_t utime);
    // RUN_EVENT stop/abort (or a late point after it, keep_after_stop): the final fit of every
    // unit heard, made at `stop_utime`; then the run's data are dropped unless keep_after_stop.
    std::vector<FitJob> FinishJobs(int64_t stop_utime);
    FitJob Job(const std::string& sensor_id, int64_t utime, bool is_final) const;
    // The fit of a job. Const and self-contained: safe on another thread while this fitter takes
    // more samples.
    RampFitResult Run(const FitJob& job) const;

    // The same at once, on the caller's thread (the virtual lab, tests).
    std::vector<RampFitResult> OnTime(int64_t utime);
    std::vector<RampFitResult> Finish(int64_t stop_utime);
    RampFitResult Fit(const std::string& sensor_id, int64_t utime, bool is_final) const;

    const std::string& run_id() const { return run_id_; }
    bool stopped() const { return stopped_; }            // the current run's stop has been seen
    size_t samples(const std::string& sensor_id) const;  // clean samples binned in this run
    size_t MemoryBytes() const { return binner_->MemoryBytes(); }
    const RampFitterOptions& options() const { return options_; }

private:
    RampFitterOptions options_;
    std::string run_id_;
    bool stopped_ = false;
    std::unique_ptr<analysis::RunBinner> binner_;
    std::map<std::string, int64_t> last_fit_utime_;
};

}  // namespace gyrocal::fitter
