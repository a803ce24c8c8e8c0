#pragma once
// The text of gyrocal_model.h, compiled in at build time: what the firmware header export
// carries verbatim, so that the firmware runs the very code the C++ libraries run.
#include <string_view>

namespace gyrocal::model {

std::string_view CModelSource();

}  // namespace gyrocal::model
