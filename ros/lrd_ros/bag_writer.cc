#include "lrd_ros/bag_writer.h"

#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <tf2_msgs/TFMessage.h>

#include <Eigen/Geometry>

#include "lrd/util/atomic_file.h"
#include "lrd/util/error.h"
#include "lrd_ros/image_messages.h"
#include "lrd_ros/pose_messages.h"

namespace lrd_ros {

namespace {

tf2_msgs::TFMessage tf_message(const lrd::io::StampedPose& p, const BagLayout& layout) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = to_stamp(p.timestamp);
  t.header.frame_id = layout.topics.gt_parent;
  t.child_frame_id = layout.topics.gt_child;
  t.transform = transform_message(p.pose);
  tf2_msgs::TFMessage m;
  m.transforms.push_back(t);
  return m;
}

}  // namespace

void write_bag(const lrd::io::FrameSource& source, const lrd::camera::PinholeCamera& camera,
               const std::filesystem::path& file, const BagLayout& layout) {
  // Whole or not at all: rosbag writes the temporary, renamed over `file` once closed; a failure
  // (a frame that does not load, a full disk) leaves a bag already there as it was.
  lrd::util::AtomicFile out(file);
  try {
    rosbag::Bag bag(out.temporary().string(), rosbag::bagmode::Write);
    for (std::size_t i = 0; i < source.size(); ++i) {
      const lrd::io::FrameEntry& e = source.entry(i);
      const lrd::io::RgbdFrame f = source.load_rgbd(i, camera.depth_map_factor);
      const ros::Time t_rgb = to_stamp(e.timestamp), t_depth = to_stamp(e.depth_timestamp);
      bag.write(layout.topics.rgb, t_rgb, colour_message(f.rgb, t_rgb, layout.rgb_frame));
      bag.write(layout.topics.camera_info, t_rgb, camera_info_message(camera, t_rgb, layout.rgb_frame));
      bag.write(layout.topics.depth, t_depth, depth_message(f.depth, t_depth, layout.depth_frame));
      bag.write(layout.depth_camera_info, t_depth, camera_info_message(camera, t_depth, layout.depth_frame));
    }
    if (const auto gt = source.ground_truth())
      for (const lrd::io::StampedPose& p : *gt)
        bag.write("/tf", to_stamp(p.timestamp), tf_message(p, layout));
    bag.close();
  } catch (const rosbag::BagException& e) {
    throw lrd::file_error(file, std::string("cannot write the bag: ") + e.what());
  }
  out.commit();
}

}  // namespace lrd_ros
