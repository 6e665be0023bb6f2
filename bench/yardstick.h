#pragma once
// The yardstick Y (lrd/util/yardstick.h), by the names the benchmarks use.
#include "lrd/util/yardstick.h"

namespace lrd::bench {

using util::median_of;
using util::yardstick_ms;

}  // namespace lrd::bench
