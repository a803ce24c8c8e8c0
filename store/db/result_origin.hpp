#pragma once
// Where a tool's stored result about one sensor of a recorded run came from (tables analyses and
// validations): the run and sensor, when, which software, which command line.
#include <cstdint>
#include <string>

#include "store/db/sqlite_db.hpp"

namespace gyrocal::db {

struct ResultOrigin {
    std::string run_id, sensor_id;   // the run (must exist) and sensor the result is about
    int64_t created_wall_utime = 0;  // [us] wall clock; <= 0 on insert = now
    std::string software_version, command_line;
};

// The origin's columns, in the order BindResultOrigin binds them.
inline constexpr const char* kResultOriginColumns =
    "run_id, sensor_id, created_wall_utime, software_version, command_line";

// Binds the origin to an insert's parameters 1 to 5 (kResultOriginColumns) as stored: created
// now when not set, the command line without the credentials of a database URL in it. Returns
// the next parameter, 6.
int BindResultOrigin(Stmt& s, const ResultOrigin& o);

}  // namespace gyrocal::db
