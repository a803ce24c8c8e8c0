#pragma once
// Conversion between the library's Model/CoeffSet and the wire types model_t/coeff_set_t.
// FromMsg validates everything a consumer relies on and throws ModelError naming the field, so a
// bad coefficient set is refused whole (never half-applied); ToMsg fills the length fields from
// the vectors so an encoded message is always self-consistent.
#include <cstdint>
#include <string>
#include <vector>

#include "gyrocal/coeff_set_t.hpp"
#include "gyrocal/model_t.hpp"
#include "processors/model/model.hpp"

namespace gyrocal::model {

// Where a coefficient set came from (CoeffSet::source, coeff_set_t.source), written once:
//   "fitter"        the fitter's: on a plateau run the plateau set (plateau means only, the
//                   seed's method and its N-point extension); on a ramp run the fit on every
//                   still bin
//   "closed-loop"   a plateau run's final set: every still sample, the terms the data confirm
//                   (gyrocal-fitter's closed loop, processors/fitter/ramp_fitter.hpp)
//   "analysis:<id>" the extended model of `gyrocal analyze` (analysis <id> in the database)
inline constexpr const char* kFitterSource = "fitter";
inline constexpr const char* kClosedLoopSource = "closed-loop";

// A calibration of one unit: what the compensator applies.
struct CoeffSet {
    int64_t utime = 0;  // [us] newest input used
    std::string sensor_id;
    std::string run_id;
    int64_t coeff_set_id = 0;  // [us] = utime of the newest input
    std::string source;        // kFitterSource, kClosedLoopSource, "analysis:<id>" (above)
    Model offset;              // quantity offset_v
    Model sensitivity;         // quantity sensitivity_v_per_dps
    std::vector<int64_t> plateau_ids;
    std::vector<int64_t> rotation_ids;
};

// The fields a model's forms (Model, model_t, the store's ModelRow) share by name, copied from
// one to another; coefficients and covariance differ in container and are each conversion's own.
template <class To, class From>
void CopyModelScalars(To& to, const From& from) {
    to.quantity = from.quantity;
    to.term_names = from.term_names;
    to.t0_c = from.t0_c;
    to.temp_min_c = from.temp_min_c;
    to.temp_max_c = from.temp_max_c;
    to.residual_rms = from.residual_rms;
    to.n_points = from.n_points;
    to.condition_number = from.condition_number;
    to.method = from.method;
}

// A set's key (run, sensor, coeff_set_id, source) and time, as a set carries them and as what
// names a set carries them (a fit report, an analysis: store/recorder/message_fields.hpp).
template <class To, class From>
void CopySetKey(To& to, const From& from) {
    to.utime = from.utime;
    to.sensor_id = from.sensor_id;
    to.run_id = from.run_id;
    to.coeff_set_id = from.coeff_set_id;
    to.source = from.source;
}

// The same for a set's identity and evidence (CoeffSet, coeff_set_t, CoeffSetRow); the models
// and the message's length fields are each conversion's own.
template <class To, class From>
void CopySetIdentity(To& to, const From& from) {
    CopySetKey(to, from);
    to.plateau_ids = from.plateau_ids;
    to.rotation_ids = from.rotation_ids;
}

// Throws ModelError on inconsistent array lengths, unknown/duplicate terms, non-finite values.
Model FromMsg(const gyrocal::model_t& msg);
gyrocal::model_t ToMsg(const Model& model);

// Also checks the quantities ("offset_v", "sensitivity_v_per_dps") and the id arrays.
CoeffSet FromMsg(const gyrocal::coeff_set_t& msg);
gyrocal::coeff_set_t ToMsg(const CoeffSet& set);

}  // namespace gyrocal::model
