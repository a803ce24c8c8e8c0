#include "processors/model/model.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "lcmtypes/text/names.hpp"

namespace gyrocal::model {

namespace {

constexpr text::NameTable<RangePolicy, 2> kRangePolicyNames{
    {{RangePolicy::kClip, "clip"}, {RangePolicy::kExtrapolate, "extrapolate"}}};

}  // namespace

std::optional<RangePolicy> ParseRangePolicy(const std::string& name) {
    return text::ValueOf(kRangePolicyNames, name);
}

const char* ToString(RangePolicy policy) { return text::NameOf(kRangePolicyNames, policy); }

std::string Validate(const Model& m) {
    const auto n = static_cast<Eigen::Index>(m.term_names.size());
    const std::string q = m.quantity.empty() ? "model" : m.quantity;
    if (n == 0) return q + ": no terms (num_terms must be >= 1)";
    if (m.coeffs.size() != n)
        return q + ": coeffs has " + std::to_string(m.coeffs.size()) + " values for " +
               std::to_string(n) + " terms";
    if (m.covariance.rows() != n || m.covariance.cols() != n)
        return q + ": covariance is " + std::to_string(m.covariance.rows()) + "x" +
               std::to_string(m.covariance.cols()) + ", must be " + std::to_string(n) + "x" +
               std::to_string(n);
    std::set<std::string> seen;
    for (const std::string& name : m.term_names) {
        std::string error;
        if (!ResolveTerm(name, nullptr, &error)) return q + ": " + error;
        if (!seen.insert(name).second) return q + ": term '" + name + "' appears twice";
    }
    for (Eigen::Index i = 0; i < n; ++i)
        if (!std::isfinite(m.coeffs[i]))
            return q + ": coefficient of '" + m.term_names[i] + "' is not finite";
    if (!std::isfinite(m.t0_c)) return q + ": t0_c is not finite";
    if (!std::isfinite(m.temp_min_c) || !std::isfinite(m.temp_max_c) || m.temp_min_c > m.temp_max_c)
        return q + ": valid range temp_min_c..temp_max_c (" + std::to_string(m.temp_min_c) + ".." +
               std::to_string(m.temp_max_c) + ") must be finite with min <= max";
    return "";
}

std::vector<ResolvedTerm> ResolveTerms(const std::vector<std::string>& names) {
    std::vector<ResolvedTerm> terms(names.size());
    for (size_t i = 0; i < names.size(); ++i) {
        std::string error;
        if (!ResolveTerm(names[i], &terms[i], &error)) throw ModelError(error);
    }
    return terms;
}

Eigen::VectorXd TermValues(const std::vector<ResolvedTerm>& terms, double t0_c,
                           const ModelInputs& in) {
    Eigen::VectorXd phi(static_cast<Eigen::Index>(terms.size()));
    const double dT = in.temp_c - t0_c;
    for (size_t i = 0; i < terms.size(); ++i) phi[static_cast<Eigen::Index>(i)] = terms[i](dT, in);
    return phi;
}

Evaluator::Evaluator(Model model) : model_(std::move(model)) {
    const std::string problem = Validate(model_);
    if (!problem.empty()) throw ModelError(problem);
    terms_ = ResolveTerms(model_.term_names);
    for (const ResolvedTerm& t : terms_) c_terms_.push_back(t.c);
}

gyrocal_model_t Evaluator::CView() const {
    gyrocal_model_t m;
    m.num_terms = static_cast<int>(c_terms_.size());
    m.term_names = nullptr;
    m.terms = c_terms_.data();
    m.coeffs = model_.coeffs.data();
    m.t0_c = model_.t0_c;
    m.temp_min_c = model_.temp_min_c;
    m.temp_max_c = model_.temp_max_c;
    return m;
}

bool Evaluator::InRange(double temp_c) const {
    return temp_c >= model_.temp_min_c && temp_c <= model_.temp_max_c;
}

Eigen::VectorXd Evaluator::TermValues(const ModelInputs& in) const {
    return model::TermValues(terms_, model_.t0_c, in);
}

int CPolicy(RangePolicy policy) {
    return policy == RangePolicy::kClip ? GYROCAL_CLIP : GYROCAL_EXTRAPOLATE;
}

Evaluation Evaluator::Evaluate(const ModelInputs& in, RangePolicy policy) const {
    Evaluation out;
    if (!std::isfinite(in.temp_c)) return out;  // value NaN: no temperature, no number
    const gyrocal_model_t m = CView();
    int flag = GYROCAL_IN_RANGE;
    out.value = gyrocal_eval_policy(&m, &in, CPolicy(policy), &flag);
    out.range = static_cast<RangeFlag>(flag);
    ModelInputs used = in;
    if (out.range == RangeFlag::kClipped)
        used.temp_c = std::clamp(in.temp_c, model_.temp_min_c, model_.temp_max_c);
    const Eigen::VectorXd phi = TermValues(used);
    out.variance = phi.dot(model_.covariance * phi);
    return out;
}

Evaluation Evaluate(const Model& model, const ModelInputs& in, RangePolicy policy) {
    return Evaluator(model).Evaluate(in, policy);
}

}  // namespace gyrocal::model
