#include "producers/sim_rig/truth_file.hpp"

#include <cstdio>
#include <fstream>

#include "producers/sim/truth.hpp"

namespace gyrocal::sim_rig {

bool WriteTruthFile(const std::string& path, const SimRigOptions& o, std::string& error) {
    // Written before the first sample, atomically (temp file + rename), so a reader never sees
    // half a file and a killed run still has its truth.
    sim::Rig rig(o.rig);
    nlohmann::json j = sim::TruthJson(rig);
    j["mode"] = o.mode;
    if (o.mode == "builtin") j["profile_setpoints_c"] = o.profile.setpoints_c;
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp);
        if (!f) {
            error = "--truth-out '" + path + "': cannot open '" + tmp + "' for writing";
            return false;
        }
        f << j.dump(2) << "\n";
        if (!f.flush()) {
            error = "--truth-out '" + path + "': write failed";
            return false;
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        error = "--truth-out '" + path + "': cannot rename '" + tmp + "' into place";
        return false;
    }
    return true;
}

}  // namespace gyrocal::sim_rig
