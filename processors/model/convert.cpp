#include "processors/model/convert.hpp"

namespace gyrocal::model {

Model FromMsg(const gyrocal::model_t& msg) {
    const std::string q = msg.quantity.empty() ? "model" : msg.quantity;
    const size_t n = msg.num_terms < 0 ? 0 : static_cast<size_t>(msg.num_terms);
    if (msg.num_terms < 1)
        throw ModelError(q + ": num_terms is " + std::to_string(msg.num_terms) + ", must be >= 1");
    if (msg.term_names.size() != n || msg.coeffs.size() != n || msg.covariance.size() != n)
        throw ModelError(q + ": num_terms " + std::to_string(n) + " does not match term_names (" +
                         std::to_string(msg.term_names.size()) + "), coeffs (" +
                         std::to_string(msg.coeffs.size()) + ") or covariance rows (" +
                         std::to_string(msg.covariance.size()) + ")");
    Model m;
    CopyModelScalars(m, msg);
    m.coeffs.resize(static_cast<Eigen::Index>(n));
    m.covariance.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    for (size_t i = 0; i < n; ++i) {
        m.coeffs[static_cast<Eigen::Index>(i)] = msg.coeffs[i];
        if (msg.covariance[i].size() != n)
            throw ModelError(q + ": covariance row " + std::to_string(i) + " has " +
                             std::to_string(msg.covariance[i].size()) + " values, must be " +
                             std::to_string(n));
        for (size_t j = 0; j < n; ++j)
            m.covariance(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
                msg.covariance[i][j];
    }
    const std::string problem = Validate(m);
    if (!problem.empty()) throw ModelError(problem);
    return m;
}

gyrocal::model_t ToMsg(const Model& m) {
    const std::string problem = Validate(m);
    if (!problem.empty()) throw ModelError(problem);
    gyrocal::model_t msg;
    const auto n = static_cast<size_t>(m.term_names.size());
    CopyModelScalars(msg, m);
    msg.num_terms = static_cast<int16_t>(n);
    msg.coeffs.assign(m.coeffs.data(), m.coeffs.data() + n);
    msg.covariance.assign(n, std::vector<double>(n));
    for (size_t i = 0; i < n; ++i)
        for (size_t j = 0; j < n; ++j)
            msg.covariance[i][j] =
                m.covariance(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
    return msg;
}

namespace {
void CheckQuantity(const Model& m, const char* want, const char* field) {
    if (m.quantity != want)
        throw ModelError(std::string(field) + ".quantity is '" + m.quantity + "', must be '" +
                         want + "'");
}
}  // namespace

CoeffSet FromMsg(const gyrocal::coeff_set_t& msg) {
    if (msg.num_plateaus < 0 || static_cast<size_t>(msg.num_plateaus) != msg.plateau_ids.size())
        throw ModelError("num_plateaus " + std::to_string(msg.num_plateaus) +
                         " does not match plateau_ids (" + std::to_string(msg.plateau_ids.size()) +
                         ")");
    if (msg.num_rotations < 0 || static_cast<size_t>(msg.num_rotations) != msg.rotation_ids.size())
        throw ModelError("num_rotations " + std::to_string(msg.num_rotations) +
                         " does not match rotation_ids (" +
                         std::to_string(msg.rotation_ids.size()) + ")");
    CoeffSet set;
    CopySetIdentity(set, msg);
    try {
        set.offset = FromMsg(msg.offset);
    } catch (const ModelError& e) {
        throw ModelError(std::string("offset: ") + e.what());
    }
    try {
        set.sensitivity = FromMsg(msg.sensitivity);
    } catch (const ModelError& e) {
        throw ModelError(std::string("sensitivity: ") + e.what());
    }
    CheckQuantity(set.offset, kOffsetQuantity, "offset");
    CheckQuantity(set.sensitivity, kSensitivityQuantity, "sensitivity");
    return set;
}

gyrocal::coeff_set_t ToMsg(const CoeffSet& set) {
    CheckQuantity(set.offset, kOffsetQuantity, "offset");
    CheckQuantity(set.sensitivity, kSensitivityQuantity, "sensitivity");
    gyrocal::coeff_set_t msg;
    CopySetIdentity(msg, set);
    msg.offset = ToMsg(set.offset);
    msg.sensitivity = ToMsg(set.sensitivity);
    msg.num_plateaus = static_cast<int32_t>(set.plateau_ids.size());
    msg.num_rotations = static_cast<int32_t>(set.rotation_ids.size());
    return msg;
}

}  // namespace gyrocal::model
