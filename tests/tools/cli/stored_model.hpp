#pragma once
// A coefficient set read back from the database an end-to-end test produced.
#include <cmath>
#include <string>

#include "processors/model/model.hpp"
#include "tests/tools/cli/e2e_support.hpp"

namespace gyrocal {

// The coeff_row_id of the newest coefficient set stored for `sensor_id` in `run_id` (at the end
// of a run, its final one), "" when there is none.
inline std::string NewestCoeffRow(Sql& sql, const std::string& run_id,
                                  const std::string& sensor_id) {
    return sql
        .Rows("SELECT max(coeff_row_id) FROM coeff_sets WHERE run_id='" + run_id +
              "' AND sensor_id='" + sensor_id + "'")
        .at(0)
        .at(0);
}

// The model of the coefficient set in row `row` as stored (coeff_models, coeff_terms,
// coeff_covariance; role offset|sensitivity): terms, coefficients, covariance (NULL: NaN).
inline model::Model StoredModel(Sql& sql, const std::string& row, const std::string& role) {
    model::Model m;
    const std::string where = " WHERE coeff_row_id=" + row + " AND role='" + role + "'";
    const auto meta =
        sql.Rows("SELECT quantity, t0_c, temp_min_c, temp_max_c, method FROM coeff_models" + where);
    m.quantity = meta.at(0).at(0);
    m.t0_c = std::stod(meta.at(0).at(1));
    m.temp_min_c = std::stod(meta.at(0).at(2));
    m.temp_max_c = std::stod(meta.at(0).at(3));
    m.method = meta.at(0).at(4);
    const auto terms =
        sql.Rows("SELECT term_name, coeff FROM coeff_terms" + where + " ORDER BY term_index");
    m.coeffs.resize(static_cast<Eigen::Index>(terms.size()));
    for (size_t i = 0; i < terms.size(); ++i) {
        m.term_names.push_back(terms[i][0]);
        m.coeffs[static_cast<Eigen::Index>(i)] = std::stod(terms[i][1]);
    }
    m.covariance = Eigen::MatrixXd::Zero(m.coeffs.size(), m.coeffs.size());
    for (const auto& c :
         sql.Rows("SELECT row_index, col_index, value FROM coeff_covariance" + where))
        m.covariance(std::stoi(c[0]), std::stoi(c[1])) = c[2].empty() ? NAN : std::stod(c[2]);
    return m;
}

}  // namespace gyrocal
