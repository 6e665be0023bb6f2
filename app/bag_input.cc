#include "app/bag_input.h"

#include "lrd/util/error.h"

#ifdef LRD_HAVE_ROS
#include "lrd/config/orbslam_settings.h"
#include "lrd/io/tum_sequence.h"
#include "lrd_ros/bag_sequence.h"
#include "lrd_ros/bag_writer.h"
#endif

namespace lrd::app {

#ifdef LRD_HAVE_ROS

std::shared_ptr<const io::FrameSource> open_bag(const BagCli& cli) {
  lrd_ros::BagTopics topics;
  topics.rgb = cli.rgb_topic;
  topics.depth = cli.depth_topic;
  topics.camera_info = cli.camera_info_topic;
  if (!cli.gt_from_tf.empty())
    std::tie(topics.gt_parent, topics.gt_child) = lrd_ros::parse_tf_pair(cli.gt_from_tf);
  return lrd_ros::BagSequence::open(cli.bag, topics);
}

void write_folder_as_bag(const std::filesystem::path& folder, const std::filesystem::path& bag) {
  const io::TumSequence seq = io::TumSequence::open(folder);
  const config::Settings settings = config::read_orbslam_settings(folder / "settings.yaml");
  lrd_ros::write_bag(seq, settings.camera, bag);
}

#else

namespace {
[[noreturn]] void no_ros() {
  throw Error(
      "this lrdslam was built without ROS 1: --bag needs it (scripts/install-deps.sh installs it; then "
      "rebuild)");
}
}  // namespace

std::shared_ptr<const io::FrameSource> open_bag(const BagCli& /*cli*/) {
  no_ros();
}
void write_folder_as_bag(const std::filesystem::path& /*folder*/, const std::filesystem::path& /*bag*/) {
  no_ros();
}

#endif

}  // namespace lrd::app
