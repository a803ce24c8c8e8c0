#pragma once
// Where a (re)started recorder continues: the newest run that has a start but no stop and was
// started on this recorder's bus (the group and port of the run configuration's "lcm_url"). A
// run whose configuration names no bus (a sequencer started by hand) may be any bus's. Two
// chambers recording into one database on their own ports therefore never continue each
// other's runs.
#include <string>

#include "store/db/sqlite_db.hpp"

namespace gyrocal::recorder {

// "" when there is none.
std::string OpenRunOnBus(db::Db& db, const std::string& lcm_url);

}  // namespace gyrocal::recorder
