#pragma once
// The check of a configuration's Validate() (docs/developing.md, Names: "" when valid, else one
// line naming the option or field): each bad value is tried on its own copy of a valid
// configuration, and a failure prints the message that was given.
#include <gmock/gmock.h>

#include <string>

namespace gyrocal::testing {

// `change` applied to a copy of `valid` makes Validate() name `named`; returns the changed copy
// (for a test that also shows what refuses it).
template <class Config, class Change>
Config ExpectRefusedNaming(Config valid, Change change, const std::string& named) {
    change(valid);
    EXPECT_THAT(valid.Validate(), ::testing::HasSubstr(named));
    return valid;
}

}  // namespace gyrocal::testing
