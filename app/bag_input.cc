#include "app/bag_input.h"

#include "lrd/bag/bag_layout.h"
#include "lrd/config/orbslam_settings.h"
#include "lrd/io/tum_sequence.h"
#include "lrd/rosbag2/rosbag2_sequence.h"
#include "lrd/rosbag2/rosbag2_writer.h"
#include "lrd/util/error.h"

#ifdef LRD_HAVE_ROS
#include "lrd_ros/bag_sequence.h"
#include "lrd_ros/bag_writer.h"
#endif

namespace lrd::app {

namespace fs = std::filesystem;

namespace {

bool is_rosbag2(const fs::path& bag) {
  std::error_code ec;
  return rosbag2::is_rosbag2_path(bag) || fs::is_directory(bag, ec);
}

#ifndef LRD_HAVE_ROS
[[noreturn]] void no_ros() {
  throw Error(
      "this lrdslam was built without ROS 1: a ROS 1 .bag needs it (scripts/install-deps.sh installs it; "
      "then "
      "rebuild). ROS 2 bags (.mcap, .db3, rosbag2 folders) need no ROS");
}
#endif

}  // namespace

std::shared_ptr<const io::FrameSource> open_bag(const BagCli& cli) {
  bag::BagTopics topics;
  topics.rgb = cli.rgb_topic;
  topics.depth = cli.depth_topic;
  topics.camera_info = cli.camera_info_topic;
  if (!cli.gt_from_tf.empty())
    std::tie(topics.gt_parent, topics.gt_child) = bag::parse_tf_pair(cli.gt_from_tf);
  if (is_rosbag2(cli.bag)) return rosbag2::Rosbag2Sequence::open(cli.bag, topics);
#ifdef LRD_HAVE_ROS
  return lrd_ros::BagSequence::open(cli.bag, topics);
#else
  no_ros();
#endif
}

void write_folder_as_bag(const fs::path& folder, const fs::path& bag) {
  const io::TumSequence seq = io::TumSequence::open(folder);
  const config::Settings settings = config::read_orbslam_settings(folder / "settings.yaml");
  if (rosbag2::is_rosbag2_path(bag)) return rosbag2::write_rosbag2(seq, settings.camera, bag);
#ifdef LRD_HAVE_ROS
  lrd_ros::write_bag(seq, settings.camera, bag);
#else
  no_ros();
#endif
}

}  // namespace lrd::app
