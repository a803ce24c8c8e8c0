// Development program (not a test, not a benchmark of record), issue 23's rig diagnosis: why the
// closed loop's final set, fitted on every still bin of a plateau run (profile six), drifts 4x the
// plateau set's on a quiet held-out record when the rig's temperature sensor lags its die by 15 s.
//
// Per seed and unit, on the same lab run as gyrocal_bench_closed_loop (profile six, closed loop,
// --quiet-calibration: bias instability and rate random walk off in the calibration too):
//   truth      the unit's offset curve f(T_die) = o0 + o1 dT + o2 dT^2 (dT = T_die - 25), written
//              in the measured temperature (T_meas = T_die + sensor offset at rest)
//   sets       the final set's offset terms and coefficients; its static error (dynamic terms 0)
//              e(T) = set(T_meas) - f(T_die) at a few die temperatures, in deg/h (/ S0)
//   offline    least-squares fits on the run's still bins (the closed loop's BinSnapshot) with:
//                refit      the final set's terms (must give its coefficients)
//                static     its static terms only (temp_rate dropped)
//                plateau    static terms on the plateau-window bins only
//                slow       the final set's terms on bins with |dT/dt| < --slow-c-per-min
//                +dT*dTdt   the final set's terms (+ dTdt) + a dT x dTdt column (a product term)
//                shifted    static terms at T + lag x dTdt (lag --shift-s), + dTdt
//              each one's model-only drift on the held-out record (its static part: any
//              g(T) x dT/dt integrates to G(T_end) - G(T_start) = 0 over the 25 -> 25 record)
//   the truth's residual on the bins r = y - f(T_meas - offset), regressed on [1, dTdt, dT dTdt]:
//              the lag predicts r = f'(T) lag dT/dt = o1 lag dTdt + 2 o2 lag dT dTdt
//   the final set's held-out model-only drift split by temperature band of the record
// Held-out: the benchmark's quiet record (25 -> -40 -> 85 -> 25 degC at 0.5 degC/min), the sets'
// static parts (and the final set whole) applied by the compensator's library (clip);
// model-only drift = (set's integrated error - truth @ T_meas's) / duration [deg/h], signed.
#include <CLI/CLI.hpp>
#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "processors/analysis/analyze.hpp"
#include "processors/analysis/regress.hpp"
#include "processors/model/inputs.hpp"
#include "processors/model/terms.hpp"
#include "tests/support/virtual_lab/held_out.hpp"
#include "tests/support/virtual_lab/virtual_lab.hpp"

namespace {

using namespace gyrocal;

bool IsStatic(const std::string& term) {
    return term == "1" || term == "dT" || term == "dT^2" || term == "dT^3" ||
           term.rfind("knot_", 0) == 0;
}

// A static offset model of `terms` with `coeffs`, the rest (range, t0) as `like`.
model::Model StaticModel(const model::Model& like, const std::vector<std::string>& terms,
                         const Eigen::VectorXd& coeffs) {
    model::Model m = like;
    m.term_names = terms;
    m.coeffs = coeffs;
    m.covariance = Eigen::MatrixXd::Zero(coeffs.size(), coeffs.size());
    return m;
}

// The static part of a model (its static terms and their coefficients).
model::Model StaticPart(const model::Model& m) {
    std::vector<std::string> terms;
    std::vector<double> c;
    for (size_t j = 0; j < m.term_names.size(); ++j)
        if (IsStatic(m.term_names[j]))
            terms.push_back(m.term_names[j]), c.push_back(m.coeffs[static_cast<Eigen::Index>(j)]);
    return StaticModel(m, terms, Eigen::Map<Eigen::VectorXd>(c.data(), c.size()));
}

double StaticValue(const model::Model& m, double temp_c) {
    return model::Evaluate(m, model::SteadyStateInputs(m, temp_c), model::RangePolicy::kExtrapolate)
        .value;
}

struct Fit {
    std::string name;
    std::vector<std::string> terms;  // of the coefficients (the extra columns named)
    Eigen::VectorXd coeffs;
    model::Model static_model;  // what the held-out record gets
    int n = 0;
};

Eigen::VectorXd Ols(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) {
    return x.colPivHouseholderQr().solve(y);
}

}  // namespace

int main(int argc, char** argv) {
    int seeds = 3, first_seed = 1, units = 2;
    double sensor_tau_s = NAN, slow_c_per_min = 0.1, shift_s = 15.0;
    bool quiet_calibration = true, heldout = true;
    std::string rate_term = "";
    CLI::App app{"dev_lagdiag: the closed loop's final set against the rig's truth (issue 23)"};
    app.add_option("--seeds", seeds)->capture_default_str();
    app.add_option("--first-seed", first_seed)->capture_default_str();
    app.add_option("--units", units)->capture_default_str();
    app.add_option("--sensor-tau-s", sensor_tau_s, "[s] rig temperature-sensor lag (default 15)");
    app.add_option("--slow-c-per-min", slow_c_per_min, "[degC/min] the 'slow' bins' |dT/dt| limit")
        ->capture_default_str();
    app.add_option("--shift-s", shift_s, "[s] the 'shifted' fit's lag")->capture_default_str();
    app.add_option("--rate-term", rate_term,
                   "dT/dt term for the product/shift fits when the final set has none")
        ->capture_default_str();
    app.add_flag("!--default-calibration", quiet_calibration, "calibrate on the default noise");
    app.add_flag("!--no-heldout", heldout, "skip the held-out record");
    CLI11_PARSE(app, argc, argv);

    std::map<std::string, std::vector<double>> drift_sq;  // per fit name: model-only drifts
    std::vector<std::string> fit_order;
    for (int seed = first_seed; seed < first_seed + seeds; ++seed) {
        sim::RigConfig rig = sim::RigConfig::Defaults();
        if (std::isfinite(sensor_tau_s)) rig.thermal.sensor_tau_s = sensor_tau_s;
        const sim::NoiseConfig default_noise = rig.noise;
        if (quiet_calibration)
            rig.noise.bias_instability_dps = 0, rig.noise.rate_random_walk_dps_rts = 0;
        rig.seed = static_cast<uint64_t>(seed);
        rig.num_units = units;
        virtual_lab::LabConfig c = virtual_lab::LabConfig::For("six", fit::Method::kAuto);
        c.rig = rig;
        c.closed_loop = true;
        const virtual_lab::RunResult r = virtual_lab::Run(c);
        std::vector<virtual_lab::Candidate> cands;
        std::vector<std::string> cand_names;
        auto add_cand = [&](const std::string& name, const std::string& id,
                            const model::CoeffSet& set) {
            size_t k = 0;
            while (k < cand_names.size() && cand_names[k] != name) ++k;
            if (k == cand_names.size()) cand_names.push_back(name), cands.emplace_back();
            cands[k][id] = set;
        };
        for (const sim::UnitTruth& u : r.truths) {
            const std::string& id = u.sensor_id;
            if (!r.closed_loop_sets.count(id)) continue;
            const model::CoeffSet& fin = r.closed_loop_sets.at(id);
            const model::CoeffSet& plat = r.final_sets.at(id);
            const double s0 = u.sensitivity_coeffs[0];
            const double off = u.temp_sensor_offset_c;
            auto truth_at_meas = [&](double tm) { return u.OffsetV(tm - off); };
            std::printf(
                "\nseed %d %s: truth o0 %.6f V, o1 %+.4e V/K, o2 %+.4e V/K^2 (die, about 25), "
                "sensor offset %+.3f degC, S0 %.6f V/(deg/s), package tau %.1f s\n",
                seed, id.c_str(), u.offset_coeffs[0], u.offset_coeffs[1], u.offset_coeffs[2], off,
                s0, u.package_tau_s);
            std::printf(
                "  truth in T_meas about the final set's t0 %.2f: c0 %.6f c1 %+.4e c2 %+.4e\n",
                fin.offset.t0_c, truth_at_meas(fin.offset.t0_c),
                u.offset_coeffs[1] + 2 * u.offset_coeffs[2] * (fin.offset.t0_c - off - 25),
                u.offset_coeffs[2]);
            std::printf("  final set: t0 %.2f, range %.2f..%.2f; terms", fin.offset.t0_c,
                        fin.offset.temp_min_c, fin.offset.temp_max_c);
            for (size_t j = 0; j < fin.offset.term_names.size(); ++j)
                std::printf(" %s=%+.4e", fin.offset.term_names[j].c_str(),
                            fin.offset.coeffs[static_cast<Eigen::Index>(j)]);
            std::printf("\n  plateau set: terms");
            for (size_t j = 0; j < plat.offset.term_names.size(); ++j)
                std::printf(" %s=%+.4e", plat.offset.term_names[j].c_str(),
                            plat.offset.coeffs[static_cast<Eigen::Index>(j)]);
            std::string added;
            for (const auto& a : r.closed_loop_results.at(id).added)
                added += (added.empty() ? "" : "+") + a.effect;
            std::printf("\n  analysis added: %s; verdict: %s\n",
                        added.empty() ? "-" : added.c_str(),
                        r.closed_loop_results.at(id).verdict.c_str());

            // The bins.
            const analysis::BinnedRun b =
                r.closed_loop_bins.at(id).Binned(analysis::BinOptions::Defaults());
            const double t0 = fin.offset.t0_c;
            const auto n = static_cast<Eigen::Index>(b.size());
            Eigen::VectorXd y(n), tm(n);
            Eigen::VectorXi plateau(n);
            for (Eigen::Index i = 0; i < n; ++i) {
                const analysis::Bin& x = b.bins()[static_cast<size_t>(i)];
                y[i] = x.gyro_v, tm[i] = x.temp_c, plateau[i] = x.plateau;
            }
            std::string rt = rate_term;
            for (const auto& t : fin.offset.term_names)
                if (t.rfind("dTdt", 0) == 0) rt = t;
            if (rt.empty()) rt = "dTdt(15.2)";
            const Eigen::VectorXd rate = b.Column(rt, t0);  // [degC/s]
            int n_plateau = 0, n_slow = 0, n_heat = 0, n_cool = 0;
            for (Eigen::Index i = 0; i < n; ++i) {
                n_plateau += plateau[i] >= 0;
                n_slow += std::abs(rate[i]) * 60 < slow_c_per_min;
                n_heat += rate[i] * 60 >= slow_c_per_min;
                n_cool += rate[i] * 60 <= -slow_c_per_min;
            }
            std::printf(
                "  bins %ld: plateau-window %d, |dT/dt| < %.2f degC/min %d, heating %d, cooling "
                "%d (rate term %s)\n",
                static_cast<long>(n), n_plateau, slow_c_per_min, n_slow, n_heat, n_cool,
                rt.c_str());

            // The truth's residual on the bins and the lag's prediction.
            {
                Eigen::VectorXd res(n);
                Eigen::MatrixXd x(n, 3);
                for (Eigen::Index i = 0; i < n; ++i) {
                    res[i] = y[i] - truth_at_meas(tm[i]);
                    const double dtd = tm[i] - off - 25.0;
                    x.row(i) << 1.0, rate[i], dtd * rate[i];
                }
                const Eigen::VectorXd k = Ols(x, res);
                const double lag = rig.thermal.sensor_tau_s;
                std::printf(
                    "  truth residual y - f(T_meas - off): rms %.1f uV; on [1, dTdt, dT_die*dTdt]: "
                    "%+.2f uV, %+.4e V/(degC/s) (o1 x lag %+.4e), %+.4e V/(degC^2/s) (2 o2 x lag "
                    "%+.4e); rms after %.1f uV\n",
                    1e6 * std::sqrt(res.squaredNorm() / n), 1e6 * k[0], k[1],
                    u.offset_coeffs[1] * lag, k[2], 2 * u.offset_coeffs[2] * lag,
                    1e6 * std::sqrt((res - x * k).squaredNorm() / n));
                // Its mean by segment of dT/dt sign and temperature: what the static fit sees.
                std::printf(
                    "  truth residual [uV] by T_meas band (heating / slow / cooling bins):");
                for (double lo = -45; lo < 90; lo += 25) {
                    double s[3] = {0, 0, 0};
                    int m[3] = {0, 0, 0};
                    for (Eigen::Index i = 0; i < n; ++i) {
                        if (tm[i] < lo || tm[i] >= lo + 25) continue;
                        const int g = rate[i] * 60 >= slow_c_per_min    ? 0
                                      : rate[i] * 60 <= -slow_c_per_min ? 2
                                                                        : 1;
                        s[g] += res[i], ++m[g];
                    }
                    std::printf(" [%g,%g): %+.0f(%d) %+.0f(%d) %+.0f(%d);", lo, lo + 25,
                                m[0] ? 1e6 * s[0] / m[0] : NAN, m[0],
                                m[1] ? 1e6 * s[1] / m[1] : NAN, m[1],
                                m[2] ? 1e6 * s[2] / m[2] : NAN, m[2]);
                }
                std::printf("\n");
            }

            // Offline fits.
            std::vector<std::string> st, all = fin.offset.term_names;
            for (const auto& t : all)
                if (IsStatic(t)) st.push_back(t);
            std::vector<std::string> with_rate = st;
            with_rate.push_back(rt);
            std::vector<Fit> fits;
            auto fit_rows = [&](const std::string& name, const std::vector<std::string>& terms,
                                const Eigen::MatrixXd& extra,
                                const std::vector<std::string>& extra_names,
                                const std::vector<Eigen::Index>& rows,
                                const Eigen::MatrixXd* static_cols = nullptr) {
                const Eigen::MatrixXd d = static_cols ? *static_cols : b.Design(terms, t0);
                Eigen::MatrixXd x(static_cast<Eigen::Index>(rows.size()), d.cols() + extra.cols());
                Eigen::VectorXd yy(x.rows());
                for (Eigen::Index k = 0; k < x.rows(); ++k) {
                    const Eigen::Index i = rows[static_cast<size_t>(k)];
                    x.row(k).head(d.cols()) = d.row(i);
                    if (extra.cols()) x.row(k).tail(extra.cols()) = extra.row(i);
                    yy[k] = y[i];
                }
                Fit f;
                f.name = name;
                f.terms = terms;
                f.terms.insert(f.terms.end(), extra_names.begin(), extra_names.end());
                f.coeffs = Ols(x, yy);
                f.n = static_cast<int>(x.rows());
                std::vector<std::string> sterms;
                std::vector<double> sc;
                for (size_t j = 0; j < terms.size(); ++j)
                    if (IsStatic(terms[j]))
                        sterms.push_back(terms[j]),
                            sc.push_back(f.coeffs[static_cast<Eigen::Index>(j)]);
                f.static_model = StaticModel(fin.offset, sterms,
                                             Eigen::Map<Eigen::VectorXd>(sc.data(), sc.size()));
                fits.push_back(f);
            };
            std::vector<Eigen::Index> every, on_plateau, slow;
            for (Eigen::Index i = 0; i < n; ++i) {
                every.push_back(i);
                if (plateau[i] >= 0) on_plateau.push_back(i);
                if (std::abs(rate[i]) * 60 < slow_c_per_min) slow.push_back(i);
            }
            const Eigen::MatrixXd none(n, 0);
            fit_rows("refit", all, none, {}, every);
            fit_rows("static", st, none, {}, every);
            fit_rows("plateau", st, none, {}, on_plateau);
            fit_rows("slow", all, none, {}, slow);
            {
                Eigen::MatrixXd extra(n, 1);
                const Eigen::VectorXd d = b.Column("dT", t0);
                extra.col(0) = d.cwiseProduct(rate);
                fit_rows("+dT*dTdt", with_rate, extra, {"dT*" + rt}, every);
            }
            {
                // Would the product column pass the analysis' own tests? Its blocked-CV gain
                // (AnalysisOptions: 10 blocks, 60 s guard; a candidate needs >= 2 %) and its
                // coefficient's z with the autocorrelation-robust covariance (HAC lag 30 bins),
                // on the final set's terms (+ the rate term when the set has none).
                const analysis::AnalysisOptions ao = analysis::AnalysisOptions::Defaults();
                const int guard = static_cast<int>(std::lround(ao.cv_guard_s / b.bin_s()));
                const Eigen::MatrixXd base = b.Design(with_rate, t0);
                Eigen::MatrixXd ext(n, base.cols() + 1);
                ext << base, b.Column("dT", t0).cwiseProduct(rate);
                const double mse0 = analysis::BlockedCvMse(base, y, ao.cv_blocks, guard);
                const double mse1 = analysis::BlockedCvMse(ext, y, ao.cv_blocks, guard);
                std::vector<int> seg(static_cast<size_t>(n));
                for (Eigen::Index i = 0; i < n; ++i)
                    seg[static_cast<size_t>(i)] = b.bins()[static_cast<size_t>(i)].segment;
                const analysis::LsFit f = analysis::FitLs(ext, y, seg, 30);
                const Eigen::Index last = ext.cols() - 1;
                std::printf(
                    "  dT x %s column: blocked-CV MSE %.3g -> %.3g V^2 (gain %.1f %%, the "
                    "analysis asks >= %.0f %%); coefficient %+.4e, z %.1f (HAC)\n",
                    rt.c_str(), mse0, mse1, 100 * (1 - mse1 / mse0), 100 * ao.min_cv_gain,
                    f.ok ? f.coeffs[last] : NAN,
                    f.ok ? f.coeffs[last] / std::sqrt(f.covariance(last, last)) : NAN);
            }
            {
                // Static columns at T + shift x dTdt (the die temperature the lag hides).
                Eigen::MatrixXd sc(n, static_cast<Eigen::Index>(with_rate.size()));
                for (Eigen::Index i = 0; i < n; ++i) {
                    model::ModelInputs in;  // static terms read the temperature only
                    in.temp_c = tm[i] + shift_s * rate[i];
                    const Eigen::VectorXd row = model::TermValues(model::ResolveTerms(st), t0, in);
                    sc.row(i).head(row.size()) = row;
                    sc(i, sc.cols() - 1) = rate[i];
                }
                fit_rows("shifted", with_rate, none, {}, every, &sc);
            }
            const double s_dph = 3600.0 / s0;
            std::printf("  static error e(T) = set(T_meas) - f(T_die) [deg/h] at T_die:\n");
            std::printf("  %-10s %5s", "fit", "bins");
            const std::vector<double> temps = {-40, -25, -10, 10, 25, 45, 65, 85};
            for (double t : temps) std::printf(" %8.0f", t);
            std::printf("  | mean over -40..85 | set - truth (T_meas about t0) | coefficients\n");
            auto print_err = [&](const std::string& name, int nb, const model::Model& sm,
                                 const std::string& coeffs) {
                std::printf("  %-10s %5d", name.c_str(), nb);
                for (double t : temps)
                    std::printf(" %+8.2f", s_dph * (StaticValue(sm, t + off) - u.OffsetV(t)));
                double sum = 0;
                int m = 0;
                for (double t = -40; t <= 85.001; t += 0.5, ++m)
                    sum += StaticValue(sm, t + off) - u.OffsetV(t);
                // Coefficient errors against the truth in T_meas about t0 (static terms 1, dT,
                // dT^2; a dT^3 term's share is in the curve above).
                const double d0 = sm.t0_c - off - 25.0;
                const double truth[3] = {u.OffsetV(sm.t0_c - off),
                                         u.offset_coeffs[1] + 2 * u.offset_coeffs[2] * d0,
                                         u.offset_coeffs[2]};
                double got[3] = {0, 0, 0};
                for (size_t j = 0; j < sm.term_names.size(); ++j) {
                    const int k = sm.term_names[j] == "1"      ? 0
                                  : sm.term_names[j] == "dT"   ? 1
                                  : sm.term_names[j] == "dT^2" ? 2
                                                               : -1;
                    if (k >= 0) got[k] = sm.coeffs[static_cast<Eigen::Index>(j)];
                }
                std::printf(
                    "  | %+8.2f | d1 %+6.1f uV, ddT %+6.3f uV/K, ddT^2 %+6.1f nV/K^2 | %s\n",
                    s_dph * sum / m, 1e6 * (got[0] - truth[0]), 1e6 * (got[1] - truth[1]),
                    1e9 * (got[2] - truth[2]), coeffs.c_str());
            };
            print_err("final", n, StaticPart(fin.offset), "(as published)");
            print_err("plateau", 0, StaticPart(plat.offset), "(the plateau set)");
            for (const Fit& f : fits) {
                std::string cs;
                for (size_t j = 0; j < f.terms.size(); ++j) {
                    char buf[96];
                    std::snprintf(buf, sizeof buf, "%s%s=%+.4e", j ? " " : "", f.terms[j].c_str(),
                                  f.coeffs[static_cast<Eigen::Index>(j)]);
                    cs += buf;
                }
                print_err(f.name, f.n, f.static_model, cs);
            }
            if (heldout) {
                add_cand("final", id, fin);
                model::CoeffSet s = fin;
                s.offset = StaticPart(fin.offset);
                add_cand("final static", id, s);
                add_cand("plateau set", id, plat);
                for (const Fit& f : fits) {
                    s.offset = f.static_model;
                    add_cand(f.name, id, s);
                }
            }
        }
        if (!heldout) continue;
        virtual_lab::HeldOutProfile profile;
        profile.lead_in_s = 1e-6 * static_cast<double>(r.end_utime - rig.start_utime) + 600.0;
        sim::RigConfig held = rig;
        held.noise = default_noise;
        held.noise.bias_instability_dps = 0.0, held.noise.rate_random_walk_dps_rts = 0.0;
        const auto h = virtual_lab::EvaluateHeldOut(held, profile, cands);
        std::printf(
            "\nseed %d held-out (quiet record, %.0f s): model-only drift (set - truth @ "
            "T_meas) [deg/h], signed, per unit\n",
            seed, h.duration_s);
        for (size_t k = 0; k < cands.size(); ++k) {
            if (seed == first_seed) fit_order.push_back(cand_names[k]);
            std::printf("  %-13s", cand_names[k].c_str());
            for (const auto& s : h.sensors) {
                const double d = (s.angle_deg[k] - s.floor_meas_angle_deg) / (h.duration_s / 3600);
                std::printf(" %s %+8.2f", s.sensor_id.c_str(), d);
                drift_sq[cand_names[k]].push_back(d);
            }
            std::printf("\n");
        }
        // The yardstick itself: truth @ T_meas against truth @ T_die on the same record (the
        // lag's own drift on a record that returns to its start temperature).
        std::printf("  truth @ T_meas - truth @ T_die (drift) [deg/h]:");
        for (const auto& s : h.sensors)
            std::printf(" %s %+7.3f", s.sensor_id.c_str(),
                        (s.floor_meas_angle_deg - s.floor_angle_deg) / (h.duration_s / 3600));
        std::printf("\n");
        // The final set's model-only drift by band of the record's measured temperature.
        std::printf("  final set's model-only drift by T_meas band of the record [deg/h]:\n");
        for (const auto& s : h.sensors) {
            std::printf("    %s:", s.sensor_id.c_str());
            for (double lo = -45; lo < 90; lo += 25) {
                double sum = 0;
                for (size_t i = 0; i < s.t_s.size(); ++i)
                    if (s.temp_c[i] >= lo && s.temp_c[i] < lo + 25 &&
                        std::isfinite(s.err_dps[0][i]))
                        sum += (s.err_dps[0][i] - s.floor_meas_dps[i]) * h.bin_s;
                std::printf(" [%g,%g) %+6.2f", lo, lo + 25, sum / (h.duration_s / 3600));
            }
            std::printf("\n");
        }
        std::fflush(stdout);
    }
    if (heldout) {
        std::printf("\nmodel-only drift, RMS over seeds and units [deg/h]:\n");
        for (const auto& name : fit_order) {
            const auto& v = drift_sq[name];
            double s = 0;
            for (double d : v) s += d * d;
            std::printf("  %-13s %6.2f  (%zu units)\n", name.c_str(), std::sqrt(s / v.size()),
                        v.size());
        }
    }
    return 0;
}
