#include "model_rows.hpp"

#include "model/inputs.hpp"

#include <limits>

namespace gyrocal::store {
namespace {

void CheckModels(const model::CoeffSet& set) {
    for (const model::Model* m : {&set.offset, &set.sensitivity}) {
        const std::string problem = model::Problem(*m);
        if (!problem.empty()) throw model::ModelError("coefficient set: " + problem);
    }
}

}  // namespace

ModelRow ToModelRow(const model::Model& m) {
    ModelRow r;
    r.quantity = m.quantity;
    r.term_names = m.term_names;
    r.coeffs.assign(m.coeffs.data(), m.coeffs.data() + m.coeffs.size());
    r.covariance.assign(static_cast<size_t>(m.covariance.rows()),
                        std::vector<double>(static_cast<size_t>(m.covariance.cols())));
    for (Eigen::Index i = 0; i < m.covariance.rows(); ++i)
        for (Eigen::Index j = 0; j < m.covariance.cols(); ++j)
            r.covariance[static_cast<size_t>(i)][static_cast<size_t>(j)] = m.covariance(i, j);
    r.t0_c = m.t0_c;
    r.temp_min_c = m.temp_min_c;
    r.temp_max_c = m.temp_max_c;
    r.residual_rms = m.residual_rms;
    r.n_points = m.n_points;
    r.condition_number = m.condition_number;
    r.method = m.method;
    return r;
}

model::Model ToModel(const ModelRow& r) {
    model::Model m;
    m.quantity = r.quantity;
    m.term_names = r.term_names;
    m.coeffs = Eigen::Map<const Eigen::VectorXd>(r.coeffs.data(),
                                                 static_cast<Eigen::Index>(r.coeffs.size()));
    // A ragged stored covariance becomes NaN cells (unknown), never a crash.
    const auto n = static_cast<Eigen::Index>(r.covariance.size());
    m.covariance = Eigen::MatrixXd::Constant(n, n, std::numeric_limits<double>::quiet_NaN());
    for (size_t i = 0; i < r.covariance.size(); ++i)
        for (size_t j = 0; j < r.covariance[i].size() && j < r.covariance.size(); ++j)
            m.covariance(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
                r.covariance[i][j];
    m.t0_c = r.t0_c;
    m.temp_min_c = r.temp_min_c;
    m.temp_max_c = r.temp_max_c;
    m.residual_rms = r.residual_rms;
    m.n_points = r.n_points;
    m.condition_number = r.condition_number;
    m.method = r.method;
    return m;
}

CoeffSetRow ToCoeffSetRow(const model::CoeffSet& set, int64_t recv_utime) {
    CoeffSetRow r;
    r.run_id = set.run_id;
    r.sensor_id = set.sensor_id;
    r.source = set.source;
    r.coeff_set_id = set.coeff_set_id;
    r.utime = set.utime;
    r.offset = ToModelRow(set.offset);
    r.sensitivity = ToModelRow(set.sensitivity);
    r.plateau_ids = set.plateau_ids;
    r.rotation_ids = set.rotation_ids;
    r.recv_utime = recv_utime;
    return r;
}

CoeffSetRow ToCoeffSetRow(const gyrocal::coeff_set_t& msg, int64_t recv_utime) {
    return ToCoeffSetRow(model::FromMsg(msg), recv_utime);
}

model::CoeffSet ToCoeffSet(const CoeffSetRow& r) {
    model::CoeffSet s;
    s.utime = r.utime;
    s.sensor_id = r.sensor_id;
    s.run_id = r.run_id;
    s.coeff_set_id = r.coeff_set_id;
    s.source = r.source;
    s.offset = ToModel(r.offset);
    s.sensitivity = ToModel(r.sensitivity);
    s.plateau_ids = r.plateau_ids;
    s.rotation_ids = r.rotation_ids;
    return s;
}

StoredAnalysis StoreAnalysis(Db& db, const AnalysisRow& row, const model::CoeffSet* extended) {
    if (!extended) return store::StoreAnalysis(db, row, static_cast<const CoeffSetRow*>(nullptr));
    CheckModels(*extended);
    const CoeffSetRow set = ToCoeffSetRow(*extended, 0);
    return store::StoreAnalysis(db, row, &set);
}

StoredAnalysis StoreAnalysis(Db& db, const AnalysisRow& row, const gyrocal::coeff_set_t* extended) {
    if (!extended) return store::StoreAnalysis(db, row, static_cast<const CoeffSetRow*>(nullptr));
    const model::CoeffSet set = model::FromMsg(*extended);
    return StoreAnalysis(db, row, &set);
}

int64_t StoreCoeffSet(Db& db, const model::CoeffSet& set, int64_t recv_utime) {
    CheckModels(set);
    return store::StoreCoeffSet(db, ToCoeffSetRow(set, recv_utime));
}

int64_t StoreCoeffSet(Db& db, const gyrocal::coeff_set_t& set, int64_t recv_utime) {
    return StoreCoeffSet(db, model::FromMsg(set), recv_utime);
}

std::optional<double> SteadyStateValue(const ModelRow& m, double temp_c) {
    try {
        const model::Model model = ToModel(m);
        const model::Evaluator eval(model);
        return eval.Value(model::SteadyStateInputs(model, temp_c),
                          model::RangePolicy::kExtrapolate);
    } catch (const model::ModelError&) {
        return std::nullopt;
    }
}

}  // namespace gyrocal::store
