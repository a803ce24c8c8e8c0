#pragma once
// Internal to gyrocal_analysis: the tests whose false-positive rate is measured on the run's own
// noise (noise_model.hpp) instead of set by a constant.
//
// HeldOutSearch: families of regressors, each searched over a parameter (a period, a step time, a
// time constant) on the training bins by residual sum of squares, the chosen one then predicting
// the held-out bins. Its statistic is log(|r0|^2 / |r1|^2), r0 and r1 the held-out residuals of the
// model without and with the family (both fitted on the training bins). Everything is linear in
// the data, so the columns are projected once (Frisch-Waugh: the family's coefficients come from
// its columns with the model projected out of them on the training rows) and each data vector -
// the run's or a surrogate's - costs a few dot products per searched column. A surrogate is pure
// noise: the model's columns are in both fits, so its own part would cancel anyway.
// MaxTNull: the null of a family-wise maximum. Each family's (or window's) statistic is
// standardised by its mean and standard deviation over the surrogates; the threshold is the
// (1 - alpha) quantile of the surrogates' largest standardised value. A family whose
// standardised statistic on the run exceeds it is significant with a family-wise false-positive
// rate of alpha under the run's noise (up to the surrogates' fidelity and count).
// WindowStats: the residual's mean in windows of time and temperature (the model fitted on all
// bins), the statistic of step 9's "part of the run far from the floor": what a transient, a
// shift or a bend confined to part of the run leaves there. (Its mean square would also count a
// few bins of noise burst; a periodic or a drift, whose windows' means cancel or trend, are the
// generic features' to find.)
#include <Eigen/Dense>
#include <string>
#include <vector>

namespace gyrocal::analysis::detail {

// A family of regressors searched over a parameter: element j has columns cols[j] on all bins.
struct Family {
    std::string name, channel, detail, unit, param;  // detail: prefix of the chosen parameter
    std::vector<double> grid;                        // parameter values (empty: one element)
    std::vector<Eigen::MatrixXd> cols;
    bool competes = false;  // time-shaped: may displace or mask a named candidate
};

struct FamilyFit {
    int best = -1;              // element chosen on the training bins
    double stat = NAN;          // log(|r0|^2 / |r1|^2) on the held-out bins
    Eigen::VectorXd r0, r1;     // held-out residuals without and with it (when asked)
    Eigen::VectorXd predicted;  // what it adds to the prediction on the held-out bins
};

class HeldOutSearch {
public:
    HeldOutSearch(const Eigen::MatrixXd& base_all, const std::vector<Eigen::Index>& train,
                  const std::vector<Eigen::Index>& held, const std::vector<Family>& families);
    bool ok() const { return ok_; }
    // Each family on data y (all bins); residuals kept when keep is true.
    std::vector<FamilyFit> Evaluate(const Eigen::VectorXd& y_all, bool keep) const;

private:
    struct Element {
        Eigen::MatrixXd c_res;   // columns with the model projected out (training rows)
        Eigen::MatrixXd g_inv;   // (c_res' c_res)^-1
        Eigen::MatrixXd f_held;  // held-out columns less the model's prediction of them
        bool ok = false;
    };
    bool ok_ = false;
    std::vector<Eigen::Index> train_, held_;
    Eigen::MatrixXd q_;               // orthonormal basis of the model's training columns
    Eigen::MatrixXd x_held_, solve_;  // held-out model columns; training LS operator (p x n_t)
    std::vector<std::vector<Element>> elements_;
};

class MaxTNull {
public:
    // stats[s][f]: statistic of family f on surrogate s (non-finite: left out).
    explicit MaxTNull(const std::vector<std::vector<double>>& stats);
    double Z(size_t f, double x) const;  // standardised; NaN when f has no usable null
    double Threshold(double alpha) const;
    double PValue(double z_max) const;  // share of surrogates whose largest z reaches z_max
    size_t surrogates() const { return max_z_.size(); }

private:
    std::vector<double> mean_, sd_, max_z_;  // max_z_ sorted ascending
};

// A search judged on the run's data y and on the surrogates: each family's fit on the run, its
// statistic standardised by its null (MaxTNull), the family-wise threshold at alpha, and each
// family's own p-value (share of surrogates whose statistic reaches the run's, (1 + k) / (1 + S)).
// subset: families judged as a family-wise test of their own as well (the named effects' shape
// checks, residual.hpp): subset_threshold is the same max-T threshold at alpha over those
// families alone (their z standardised as above: the same z, a smaller family).
struct NullVerdict {
    std::vector<FamilyFit> fits;
    std::vector<double> z, p;
    double threshold = NAN;
    double subset_threshold = NAN;  // NaN when subset is empty
};
NullVerdict JudgeOnNull(const HeldOutSearch& search, const Eigen::VectorXd& y_all,
                        const std::vector<Eigen::VectorXd>& surrogates, double alpha,
                        const std::vector<size_t>& subset = {});

struct WindowSpec {
    std::string where;  // "0-600 s from the start", "31-41 degC"
    std::vector<Eigen::Index> rows;
    // [s] the time the window's mean averages over: a tile's length, a band's bins x bin length
    // (the tau at which the studentised windows statistic takes the noise's Allan deviation)
    double tau_s = 0.0;
};

// |mean| of y's residual (after least squares on x_all over all bins) in each window, and (when
// ms is given) its mean square.
class WindowStats {
public:
    WindowStats(const Eigen::MatrixXd& x_all, std::vector<WindowSpec> windows);
    std::vector<double> Evaluate(const Eigen::VectorXd& y_all,
                                 std::vector<double>* ms = nullptr) const;
    // y_all with the design projected out (what Evaluate averages), and the same on a residual
    // already computed (so a caller that needs the residual itself projects once).
    Eigen::VectorXd Residual(const Eigen::VectorXd& y_all) const;
    std::vector<double> EvaluateResidual(const Eigen::VectorXd& r,
                                         std::vector<double>* ms = nullptr) const;
    const std::vector<WindowSpec>& windows() const { return windows_; }

private:
    Eigen::MatrixXd q_;
    std::vector<WindowSpec> windows_;
};

}  // namespace gyrocal::analysis::detail
