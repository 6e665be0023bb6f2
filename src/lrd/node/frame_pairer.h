#pragma once
// Colour and depth images from two subscriptions, paired by stamp as TUM's associate.py pairs a
// folder's lists (and lrd/bag a bag's): each image with the other stream's image nearest in stamp
// within max_dt, each used once, pairs in stamp order. An image that can no longer be paired (the
// other stream has moved past it, or more than `capacity` wait) is dropped and counted. Either
// stream may arrive first; any thread.
#include <cmath>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>
#include <utility>

namespace lrd::node {

template <typename Image>
class FramePairer {
 public:
  struct Stamped {
    double stamp = 0.0;
    Image image;
  };
  struct Pair {
    Stamped colour, depth;
  };

  FramePairer(double max_dt, std::size_t capacity)
      : max_dt_(max_dt), capacity_(capacity < 1 ? 1 : capacity) {}

  std::optional<Pair> add_colour(double stamp, Image image) {
    return add(stamp, std::move(image), colour_, depth_, true);
  }
  std::optional<Pair> add_depth(double stamp, Image image) {
    return add(stamp, std::move(image), depth_, colour_, false);
  }

  [[nodiscard]] std::size_t unpaired_dropped() const {
    std::lock_guard lock(mutex_);
    return dropped_;
  }

 private:
  using Queue = std::deque<Stamped>;

  std::optional<Pair> add(double stamp, Image image, Queue& mine, Queue& other, bool is_colour) {
    std::lock_guard lock(mutex_);
    std::size_t best = other.size();
    for (std::size_t i = 0; i < other.size(); ++i) {
      const double dt = std::abs(other[i].stamp - stamp);
      if (dt <= max_dt_ && (best == other.size() || dt < std::abs(other[best].stamp - stamp))) best = i;
    }
    if (best == other.size()) {
      mine.push_back({stamp, std::move(image)});
      while (mine.size() > capacity_) drop_front(mine);
      return std::nullopt;
    }
    Stamped match = std::move(other[best]);
    // What waits from before the pair can no longer pair in order.
    other.erase(other.begin(), other.begin() + static_cast<std::ptrdiff_t>(best) + 1);
    dropped_ += best;
    while (!mine.empty() && mine.front().stamp < stamp) drop_front(mine);
    Stamped self{stamp, std::move(image)};
    if (is_colour) return Pair{std::move(self), std::move(match)};
    return Pair{std::move(match), std::move(self)};
  }

  void drop_front(Queue& q) {
    q.pop_front();
    ++dropped_;
  }

  const double max_dt_;
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  Queue colour_, depth_;
  std::size_t dropped_ = 0;
};

}  // namespace lrd::node
