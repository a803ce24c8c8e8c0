#include "store/db/result_origin.hpp"

#include "store/db/central_url.hpp"
#include "store/db/utc_text.hpp"

namespace gyrocal::db {

int BindResultOrigin(Stmt& s, const ResultOrigin& o) {
    s.BindAll(o.run_id, o.sensor_id,
              o.created_wall_utime > 0 ? o.created_wall_utime : WallUtimeNow(), o.software_version,
              WithoutCredentialsIn(o.command_line));
    return 6;
}

}  // namespace gyrocal::db
