#include "store/db/model_rows.hpp"

#include <limits>

#include "processors/model/inputs.hpp"

namespace gyrocal::db {
namespace {

void CheckModels(const model::CoeffSet& set) {
    for (const model::Model* m : {&set.offset, &set.sensitivity}) {
        const std::string problem = model::Validate(*m);
        if (!problem.empty()) throw model::ModelError("coefficient set: " + problem);
    }
}

}  // namespace

ModelRow ToModelRow(const model::Model& m) {
    ModelRow r;
    model::CopyModelScalars(r, m);
    r.coeffs.assign(m.coeffs.data(), m.coeffs.data() + m.coeffs.size());
    r.covariance.assign(static_cast<size_t>(m.covariance.rows()),
                        std::vector<double>(static_cast<size_t>(m.covariance.cols())));
    for (Eigen::Index i = 0; i < m.covariance.rows(); ++i)
        for (Eigen::Index j = 0; j < m.covariance.cols(); ++j)
            r.covariance[static_cast<size_t>(i)][static_cast<size_t>(j)] = m.covariance(i, j);
    return r;
}

model::Model ToModel(const ModelRow& r) {
    model::Model m;
    model::CopyModelScalars(m, r);
    m.coeffs = Eigen::Map<const Eigen::VectorXd>(r.coeffs.data(),
                                                 static_cast<Eigen::Index>(r.coeffs.size()));
    // A ragged stored covariance becomes NaN cells (unknown), never a crash.
    const auto n = static_cast<Eigen::Index>(r.covariance.size());
    m.covariance = Eigen::MatrixXd::Constant(n, n, std::numeric_limits<double>::quiet_NaN());
    for (size_t i = 0; i < r.covariance.size(); ++i)
        for (size_t j = 0; j < r.covariance[i].size() && j < r.covariance.size(); ++j)
            m.covariance(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
                r.covariance[i][j];
    return m;
}

CoeffSetRow ToCoeffSetRow(const model::CoeffSet& set, int64_t recv_utime) {
    CoeffSetRow r;
    model::CopySetIdentity(r, set);
    r.offset = ToModelRow(set.offset);
    r.sensitivity = ToModelRow(set.sensitivity);
    r.recv_utime = recv_utime;
    return r;
}

CoeffSetRow ToCoeffSetRow(const gyrocal::coeff_set_t& msg, int64_t recv_utime) {
    return ToCoeffSetRow(model::FromMsg(msg), recv_utime);
}

model::CoeffSet ToCoeffSet(const CoeffSetRow& r) {
    model::CoeffSet s;
    model::CopySetIdentity(s, r);
    s.offset = ToModel(r.offset);
    s.sensitivity = ToModel(r.sensitivity);
    return s;
}

StoredAnalysis StoreAnalysis(Db& db, const AnalysisRow& row, const model::CoeffSet* extended) {
    if (!extended) return db::StoreAnalysis(db, row, static_cast<const CoeffSetRow*>(nullptr));
    CheckModels(*extended);
    const CoeffSetRow set = ToCoeffSetRow(*extended, 0);
    return db::StoreAnalysis(db, row, &set);
}

StoredAnalysis StoreAnalysis(Db& db, const AnalysisRow& row, const gyrocal::coeff_set_t* extended) {
    if (!extended) return db::StoreAnalysis(db, row, static_cast<const CoeffSetRow*>(nullptr));
    const model::CoeffSet set = model::FromMsg(*extended);
    return StoreAnalysis(db, row, &set);
}

int64_t StoreCoeffSet(Db& db, const model::CoeffSet& set, int64_t recv_utime) {
    CheckModels(set);
    return db::StoreCoeffSet(db, ToCoeffSetRow(set, recv_utime));
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

}  // namespace gyrocal::db
