#pragma once
// The bridge between the store's rows and the shared model library (processors/model): the
// conversions, the model-typed ways to store an analysis and a coefficient set, and the
// evaluation of a stored model by THE evaluator (model::Evaluator), so the history, the exports
// and every other consumer compute the same number. Library gyrocal_db (links
// gyrocal_db and gyrocal_model; no LCM runtime, only the generated message structs).
#include <cstdint>
#include <optional>
#include <string>

#include "gyrocal/coeff_set_t.hpp"
#include "processors/model/convert.hpp"
#include "processors/model/model.hpp"
#include "store/db/analyses.hpp"
#include "store/db/rows.hpp"

namespace gyrocal::db {

ModelRow ToModelRow(const model::Model& m);
// No validation here: model::Evaluator (or model::Validate) says whether the model is usable.
model::Model ToModel(const ModelRow& m);

// recv_utime [us]: wall clock recorded with the set (<= 0 = when it is stored).
CoeffSetRow ToCoeffSetRow(const model::CoeffSet& set, int64_t recv_utime = 0);
// Validates the message like every consumer does (model::FromMsg); throws model::ModelError.
CoeffSetRow ToCoeffSetRow(const gyrocal::coeff_set_t& msg, int64_t recv_utime = 0);
model::CoeffSet ToCoeffSet(const CoeffSetRow& row);

// What `gyrocal analyze` calls to keep its result: the analysis row and, when
// given, its extended model as a coefficient set with source "analysis:<analysis_id>" (the
// returned `source`; set it on the coeff_set_t before publishing it for a live compensator, the
// recorder then keeps it once). Both models are checked with model::Validate first; a model that
// is not usable throws model::ModelError and nothing is written. Other failures: see
// db::StoreAnalysis (NotFound for an unknown run, StoreError).
StoredAnalysis StoreAnalysis(Db& db, const AnalysisRow& row, const model::CoeffSet* extended);
StoredAnalysis StoreAnalysis(Db& db, const AnalysisRow& row, const gyrocal::coeff_set_t* extended);

// A coefficient set stored directly (not heard on the bus); returns its coeff_row_id (or the
// existing row's, same key). The models are checked first (model::ModelError).
int64_t StoreCoeffSet(Db& db, const model::CoeffSet& set, int64_t recv_utime = 0);
int64_t StoreCoeffSet(Db& db, const gyrocal::coeff_set_t& set, int64_t recv_utime = 0);

// A stored model at the steady-state inputs of temp_c [degC] (model::SteadyStateInputs: at
// rest, warmed up, nominal supply, between branches and directions), extrapolated outside its
// valid range; nullopt when the model is not usable (unknown term, no terms, bad range ...).
std::optional<double> SteadyStateValue(const ModelRow& m, double temp_c);

}  // namespace gyrocal::db
