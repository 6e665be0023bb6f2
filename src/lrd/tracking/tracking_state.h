#pragma once
#include <string_view>

namespace lrd::tracking {

// Tracking is a state machine; losing track is a state, never an error. NotLocalized: a map was
// loaded and no frame has been placed in it yet (relocalization runs on every frame until one is).
enum class TrackingState { NotInitialized, Ok, Lost, NotLocalized };

constexpr std::string_view to_string(TrackingState s) {
  switch (s) {
    case TrackingState::NotInitialized:
      return "not-initialized";
    case TrackingState::Ok:
      return "ok";
    case TrackingState::Lost:
      return "lost";
    case TrackingState::NotLocalized:
      return "not-localized";
  }
  return "?";
}

}  // namespace lrd::tracking
