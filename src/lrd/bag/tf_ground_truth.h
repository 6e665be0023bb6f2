#pragma once
// The ground truth of a bag from its /tf and /tf_static transforms (`--gt-from-tf PARENT:CHILD`),
// whatever the bag's format: CHILD's pose in PARENT at the stamp of every /tf transform on the
// chain above CHILD (the motion capture's rate), links between followed as tf2 follows them (a
// dynamic link interpolated between its neighbouring stamps, linear in translation and slerp in
// rotation; a static link at any time; no extrapolation).
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "lrd/bag/bag_layout.h"
#include "lrd/bag/stamp.h"
#include "lrd/io/trajectory.h"

namespace lrd::bag {

class TfGroundTruth {
 public:
  // One transform of a TFMessage: child's pose in parent at stamp. Leading slashes of frame ids
  // are dropped (ROS 1 bags have them, tf2 does not).
  void add(const std::string& parent, const std::string& child, const Stamp& stamp,
           const Eigen::Isometry3d& parent_from_child, bool is_static);

  // topics.gt_child's pose in topics.gt_parent. Throws lrd::Error naming `file` when there is no
  // transform at all, or none from parent to child (listing the frames there are).
  [[nodiscard]] io::Trajectory trajectory(const std::filesystem::path& file, const BagTopics& topics) const;

 private:
  struct Link {
    std::string parent;
    std::optional<Eigen::Isometry3d> fixed;                 // a /tf_static link
    std::map<std::int64_t, Eigen::Isometry3d> by_stamp_ns;  // a /tf link's samples
  };
  // The link's transform at t, or none outside its samples' span.
  [[nodiscard]] static std::optional<Eigen::Isometry3d> link_at(const Link& link, std::int64_t t_ns);
  // `frame`'s pose in `ancestor` at t, or none.
  [[nodiscard]] std::optional<Eigen::Isometry3d> pose_in(const std::string& ancestor,
                                                         const std::string& frame, std::int64_t t_ns) const;
  [[nodiscard]] std::optional<Eigen::Isometry3d> lookup(const std::string& parent, const std::string& child,
                                                        std::int64_t t_ns) const;

  std::map<std::string, Link> links_;  // by child frame
  std::size_t transforms_ = 0;
};

}  // namespace lrd::bag
