#include "store/recorder/open_run.hpp"

#include <nlohmann/json.hpp>

#include "lcmtypes/bus/bus.hpp"

namespace gyrocal::recorder {

std::string OpenRunOnBus(db::Db& db, const std::string& lcm_url) {
    const std::optional<bus::UdpmAddress> mine = bus::ParseUdpm(lcm_url);
    db::Stmt s(
        db,
        "SELECT run_id, config_json FROM runs WHERE run_id != '' AND started_utime IS NOT NULL "
        "AND stopped_utime IS NULL AND outcome = 'running' "
        "ORDER BY first_recv_utime DESC, rowid DESC");
    while (s.Step()) {
        const nlohmann::json config =
            nlohmann::json::parse(s.Text(1), nullptr, /*allow_exceptions=*/false);
        const auto url = config.is_object() ? config.find("lcm_url") : config.end();
        if (!config.is_object() || url == config.end() || !url->is_string()) return s.Text(0);
        const std::string theirs = url->get<std::string>();
        const std::optional<bus::UdpmAddress> other = bus::ParseUdpm(theirs);
        if (mine && other ? *mine == *other : theirs == lcm_url) return s.Text(0);
    }
    return "";
}

}  // namespace gyrocal::recorder
