// The lab layout and crash policy of `gyrocal calibrate` (lab.hpp): pure rules.
#include "tools/supervisor/lab.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace gyrocal::supervisor {
namespace {

const std::vector<std::string> kAll = {
    "gyrocal-sim-rig",     "gyrocal-sequencer", "gyrocal-csv-source", "gyrocal-line-source",
    "gyrocal-log-source",  "gyrocal-plateau",   "gyrocal-rotation",   "gyrocal-fitter",
    "gyrocal-compensator", "gyrocal-recorder"};

TEST(Lab, EveryProcessRunsOnExactlyOneRoleAndAllRunsEverything) {
    for (const std::string& p : kAll) {
        SCOPED_TRACE(p);
        EXPECT_TRUE(RoleRuns(Role::kAll, p));
        int roles = 0;
        for (Role r : {Role::kProducers, Role::kProcessors, Role::kRecorder})
            roles += RoleRuns(r, p) ? 1 : 0;
        EXPECT_EQ(roles, 1);
    }
    EXPECT_TRUE(RoleRuns(Role::kProducers, "gyrocal-sequencer"));
    EXPECT_TRUE(RoleRuns(Role::kProcessors, "gyrocal-fitter"));
    EXPECT_TRUE(RoleRuns(Role::kRecorder, "gyrocal-recorder"));
    EXPECT_FALSE(RoleRuns(Role::kAll, "bash"));
    for (const char* name : {"all", "producers", "processors", "recorder"})
        EXPECT_STREQ(RoleName(*ParseRole(name)), name);
    EXPECT_FALSE(ParseRole("hub").has_value());
}

TEST(Lab, SourcesAbortTheRunEverythingElseIsRestartedWithItsRecovery) {
    for (const char* p : {"gyrocal-sim-rig", "gyrocal-csv-source", "gyrocal-line-source",
                          "gyrocal-log-source", "other"})
        EXPECT_EQ(CrashPolicy(p), OnCrash::kAbortRun) << p;
    for (const char* p : {"gyrocal-sequencer", "gyrocal-plateau", "gyrocal-rotation",
                          "gyrocal-fitter", "gyrocal-compensator", "gyrocal-recorder"})
        EXPECT_EQ(CrashPolicy(p), OnCrash::kRestart) << p;
    EXPECT_EQ(RecoveryOf("gyrocal-fitter"), Recovery::kStoredPoints);
    EXPECT_EQ(RecoveryOf("gyrocal-compensator"), Recovery::kStoredCoeffs);
    EXPECT_EQ(RecoveryOf("gyrocal-sequencer"), Recovery::kResumeSequence);
    EXPECT_EQ(RecoveryOf("gyrocal-plateau"), Recovery::kNone);
    EXPECT_EQ(RecoveryOf("gyrocal-recorder"), Recovery::kNone);
}

TEST(Lab, RestartBudgetIsPerProcess) {
    RestartBudget b(2);
    EXPECT_TRUE(b.Take("gyrocal-fitter"));
    EXPECT_TRUE(b.Take("gyrocal-fitter"));
    EXPECT_FALSE(b.Take("gyrocal-fitter"));
    EXPECT_EQ(b.used("gyrocal-fitter"), 2);
    EXPECT_TRUE(b.Take("gyrocal-plateau"));
    RestartBudget none(0);
    EXPECT_FALSE(none.Take("gyrocal-plateau"));
}

TEST(Lab, ChamberMovesThePortAndKeepsTheRest) {
    const std::string url = "udpm://239.255.76.67:7667?ttl=1&recv_buf_size=4194304";
    EXPECT_EQ(ChamberUrl(url, 1), url);
    EXPECT_EQ(ChamberUrl(url, 2), "udpm://239.255.76.67:7668?ttl=1&recv_buf_size=4194304");
    EXPECT_EQ(ChamberUrl("udpm://239.255.76.67?ttl=0", 3), "udpm://239.255.76.67:7669?ttl=0");
    EXPECT_EQ(ChamberUrl("memq://", 1), "memq://") << "chamber 1 is the URL as given";
    auto refused = [](const std::string& u, int chamber, const std::string& says) {
        try {
            ChamberUrl(u, chamber);
            ADD_FAILURE() << u << " chamber " << chamber << " accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
        }
    };
    refused(url, 0, "--chamber 0: valid is 1..100");
    refused(url, 101, "valid is 1..100");
    refused("memq://", 2, "needs a udpm:// LCM URL");
    refused("udpm://239.255.76.67:65535", 2, "past 65535");
}

}  // namespace
}  // namespace gyrocal::supervisor
