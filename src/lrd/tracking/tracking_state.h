#pragma once
#include <string_view>

namespace lrd::tracking {

// Tracking is a state machine; losing track is a state, never an error.
enum class TrackingState { NotInitialized, Ok, Lost };

constexpr std::string_view to_string(TrackingState s) {
  switch (s) {
    case TrackingState::NotInitialized:
      return "not-initialized";
    case TrackingState::Ok:
      return "ok";
    case TrackingState::Lost:
      return "lost";
  }
  return "?";
}

}  // namespace lrd::tracking
