#pragma once
// The fields the per-sensor results gyrocal-plateau and gyrocal-rotation publish share by name,
// filled in one place: every result's stamp (plateau_t, sensitivity_point_t, noise_t) and the
// window of samples a plateau or a rotation was measured over (plateau_t, sensitivity_point_t,
// from plateau::Plateau and rotation::Point, which name them alike).
#include <cstdint>
#include <string>

namespace gyrocal::motion::node {

// A result about unit `sensor_id` in run `run_id` ("" = none), stamped `utime` [us].
template <class Msg>
void Stamp(Msg& m, int64_t utime, const std::string& sensor_id, const std::string& run_id) {
    m.utime = utime;
    m.sensor_id = sensor_id;
    m.run_id = run_id;
}

// The samples `w` spans: its first and last sample's utime [us] and seq, and how many it used.
template <class Msg, class Window>
void CopyWindow(Msg& m, const Window& w) {
    m.start_utime = w.start_utime;
    m.end_utime = w.end_utime;
    m.first_seq = w.first_seq;
    m.last_seq = w.last_seq;
    m.n_samples = w.n_samples;
}

}  // namespace gyrocal::motion::node
