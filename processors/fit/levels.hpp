#pragma once
// Temperature levels: the distinct temperatures a point set was measured at.
//
// Several points can belong to one chamber setpoint (the +90 and -90 rotations, a repeated
// plateau); they are replicates, not extra temperatures. Points are sorted by temp_c and a new
// level starts where the gap to the previous point exceeds `same_level_tolerance_c` (default
// 1 degC: a chamber holds a setpoint to a few tenths of a degree, and setpoints of a useful
// calibration are >= 5 degC apart, so 1 degC separates the two cases with margin both ways).
#include <cstddef>
#include <vector>

namespace gyrocal::fit {

struct Level {
    double temp_c = 0.0;          // [degC] mean temperature of the level's points
    std::vector<size_t> members;  // indices into the input
};

// Levels sorted by temperature. temps_c must be finite.
std::vector<Level> TemperatureLevels(const std::vector<double>& temps_c,
                                     double same_level_tolerance_c);

// How many of the (sorted) levels are at least min_separation_c apart: the size of the largest
// such subset, found greedily from the coldest (each next pick is the first level at least
// min_separation_c above the last pick; this is optimal for points on a line). A polynomial of
// degree d needs d + 1 temperatures that far apart to be pinned down; levels closer than that
// are still data (replicates or near-replicates), they add no capacity.
int SeparatedLevelCount(const std::vector<Level>& levels, double min_separation_c);

}  // namespace gyrocal::fit
