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
#include "model.hpp"

namespace gyrocal::model {

// A calibration of one unit: what the compensator applies.
struct CoeffSet {
    int64_t utime = 0;  // [us] newest input used
    std::string sensor_id;
    std::string run_id;
    int64_t coeff_set_id = 0;  // [us] = utime of the newest input
    std::string source;        // "fitter", "analysis:<id>"
    Model offset;              // quantity offset_v
    Model sensitivity;         // quantity sensitivity_v_per_dps
    std::vector<int64_t> plateau_ids;
    std::vector<int64_t> rotation_ids;
};

// Throws ModelError on inconsistent array lengths, unknown/duplicate terms, non-finite values.
Model FromMsg(const gyrocal::model_t& msg);
gyrocal::model_t ToMsg(const Model& model);

// Also checks the quantities ("offset_v", "sensitivity_v_per_dps") and the id arrays.
CoeffSet FromMsg(const gyrocal::coeff_set_t& msg);
gyrocal::coeff_set_t ToMsg(const CoeffSet& set);

}  // namespace gyrocal::model
