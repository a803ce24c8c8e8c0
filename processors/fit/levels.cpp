#include "processors/fit/levels.hpp"

#include <algorithm>
#include <numeric>

namespace gyrocal::fit {

std::vector<Level> TemperatureLevels(const std::vector<double>& temps_c, double tol_c) {
    std::vector<size_t> order(temps_c.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return temps_c[a] < temps_c[b]; });
    std::vector<Level> levels;
    double prev = 0.0;
    for (size_t k = 0; k < order.size(); ++k) {
        const double t = temps_c[order[k]];
        if (k == 0 || t - prev > tol_c) levels.push_back(Level{});
        levels.back().members.push_back(order[k]);
        prev = t;
    }
    for (Level& level : levels) {
        double sum = 0.0;
        for (size_t i : level.members) sum += temps_c[i];
        level.temp_c = sum / static_cast<double>(level.members.size());
    }
    return levels;
}

int SeparatedLevelCount(const std::vector<Level>& levels, double min_separation_c) {
    int count = 0;
    double last = 0.0;
    for (const Level& l : levels) {
        if (count == 0 || l.temp_c - last >= min_separation_c) {
            ++count;
            last = l.temp_c;
        }
    }
    return count;
}

}  // namespace gyrocal::fit
