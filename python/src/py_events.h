#pragma once
// System events delivered to a Python callable on the publisher's thread.
#include <pybind11/pybind11.h>

#include <memory>

#include "lrd/events/event_publisher.h"

namespace lrd::python {

// A subscriber that calls `callback(event)` with the GIL taken. An exception in the callback is
// reported once (with how many more followed, at the end) and never stops the publisher.
[[nodiscard]] std::shared_ptr<events::Subscriber> make_subscriber(pybind11::function callback);

}  // namespace lrd::python
