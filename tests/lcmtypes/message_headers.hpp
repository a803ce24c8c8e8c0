#pragma once
// The fields several message types share by name, set in one place for the tests that build
// them: a per-sensor result's stamp, the window a plateau or a rotation was measured over, and
// the identity of the process that sent a status or a flow-control message.
#include <cstdint>
#include <string>

namespace gyrocal::testing {

// A result about unit `id` in run `run_id`, stamped `utime` [us] (plateau_t,
// sensitivity_point_t, coeff_set_t, noise_t, fit_report_t).
template <class Msg>
Msg Stamped(int64_t utime, const std::string& id, const std::string& run_id) {
    Msg m{};
    m.utime = utime;
    m.sensor_id = id;
    m.run_id = run_id;
    return m;
}

// A window of unit `id`'s samples from start_utime to end_utime [us], stamped at its end and
// keyed by its start (plateau_t's plateau_id, sensitivity_point_t's rotation_id); a store row of
// one (db::PlateauRow, db::SensitivityRow) is also received at its end.
template <class Msg>
Msg WindowOf(const std::string& id, const std::string& run_id, int64_t start_utime,
             int64_t end_utime) {
    Msg m = Stamped<Msg>(end_utime, id, run_id);
    m.start_utime = start_utime;
    m.end_utime = end_utime;
    if constexpr (requires { m.plateau_id; }) {
        m.plateau_id = start_utime;
    } else {
        m.rotation_id = start_utime;
    }
    if constexpr (requires { m.recv_utime; }) m.recv_utime = end_utime;
    return m;
}

// A message sent at `utime` [us] by process `name` (pid `pid`) on host "h": the sender's identity
// as status_t and flow_ack_t carry it (`process`) and flow_mark_t (`source`).
template <class Msg>
Msg FromProcess(int64_t utime, const std::string& name, int32_t pid) {
    Msg m{};
    m.utime = utime;
    if constexpr (requires { m.process; }) {
        m.process = name;
    } else {
        m.source = name;
    }
    m.host = "h";
    m.pid = pid;
    return m;
}

}  // namespace gyrocal::testing
