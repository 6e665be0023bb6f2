#include "ros2_player.h"

#include <chrono>
#include <thread>

#include "endpoints.h"
#include "lrd/bag/camera_info.h"
#include "lrd/bag/image_pixels.h"
#include "messages.h"
#include "participant.h"
#include "sensor_msgs.h"
#include "tf2_msgs.h"

namespace lrd_ros2 {

namespace {

using Clock = std::chrono::steady_clock;

sensor_msgs_msg_dds__CameraInfo_ camera_info_message(const lrd::bag::CameraCalibration& c, double stamp,
                                                     const std::string& frame) {
  sensor_msgs_msg_dds__CameraInfo_ m{};
  m.header = header(stamp, frame);
  m.width = c.width;
  m.height = c.height;
  m.distortion_model = text(c.distortion_model);
  m.d._length = m.d._maximum = static_cast<std::uint32_t>(c.d.size());
  m.d._buffer = const_cast<double*>(c.d.data());
  std::copy(c.k.begin(), c.k.end(), m.k);
  std::copy(c.r.begin(), c.r.end(), m.r);
  std::copy(c.p.begin(), c.p.end(), m.p);
  return m;
}

struct Publishers {
  Publishers(Participant& p, const lrd::bag::BagLayout& l, const Qos& images)
      : rgb(p, dds_topic_name(l.topics.rgb), &sensor_msgs_msg_dds__Image__desc, images),
        depth(p, dds_topic_name(l.topics.depth), &sensor_msgs_msg_dds__Image__desc, images),
        rgb_info(p, dds_topic_name(l.topics.camera_info), &sensor_msgs_msg_dds__CameraInfo__desc, images),
        depth_info(p, dds_topic_name(l.depth_camera_info), &sensor_msgs_msg_dds__CameraInfo__desc, images),
        tf(p, dds_topic_name("/tf"), &tf2_msgs_msg_dds__TFMessage__desc, default_qos(100)) {}
  Writer<sensor_msgs_msg_dds__Image_> rgb, depth;
  Writer<sensor_msgs_msg_dds__CameraInfo_> rgb_info, depth_info;
  Writer<tf2_msgs_msg_dds__TFMessage_> tf;
};

void send_ground_truth(Writer<tf2_msgs_msg_dds__TFMessage_>& tf, const lrd::bag::BagLayout& l,
                       const lrd::io::StampedPose& pose) {
  geometry_msgs_msg_dds__TransformStamped_ t{};
  t.header = header(pose.timestamp, l.topics.gt_parent);
  t.child_frame_id = text(l.topics.gt_child);
  t.transform = transform_message(pose.pose);
  tf2_msgs_msg_dds__TFMessage_ m{};
  m.transforms._length = m.transforms._maximum = 1;
  m.transforms._buffer = &t;
  tf.write(m);
}

}  // namespace

PlayResult play(const lrd::io::FrameSource& source, const lrd::camera::PinholeCamera& camera,
                const PlayOptions& o) {
  Participant participant(domain_from_environment());
  Qos images = o.reliable ? default_qos(5) : sensor_data_qos();
  Publishers pub(participant, o.layout, images);
  PlayResult result;
  result.subscriber_seen = pub.rgb.wait_for_reader(o.wait_s) && pub.depth.wait_for_reader(1.0);
  const lrd::bag::CameraCalibration calibration = lrd::bag::calibration_of(camera);
  const std::optional<lrd::io::Trajectory> gt = source.ground_truth();
  std::size_t next_gt = 0;
  const std::size_t n = o.max_frames > 0 ? std::min(o.max_frames, source.size()) : source.size();
  const Clock::time_point start = Clock::now();
  const double t0 = n > 0 ? source.entry(0).timestamp : 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const lrd::io::FrameEntry& e = source.entry(i);
    const lrd::io::RgbdFrame frame = source.load_rgbd(i, o.depth_factor);
    std::this_thread::sleep_until(start + std::chrono::duration_cast<Clock::duration>(
                                              std::chrono::duration<double>((e.timestamp - t0) / o.rate)));
    for (; gt && next_gt < gt->size() && (*gt)[next_gt].timestamp <= e.timestamp; ++next_gt)
      send_ground_truth(pub.tf, o.layout, (*gt)[next_gt]);
    const lrd::bag::ImagePixels rgb = lrd::bag::colour_pixels(frame.rgb);
    const lrd::bag::ImagePixels depth = lrd::bag::depth_pixels(frame.depth);
    pub.rgb_info.write(camera_info_message(calibration, e.timestamp, o.layout.rgb_frame));
    pub.depth_info.write(camera_info_message(calibration, e.depth_timestamp, o.layout.depth_frame));
    pub.depth.write(image_message(depth, e.depth_timestamp, o.layout.depth_frame));
    pub.rgb.write(image_message(rgb, e.timestamp, o.layout.rgb_frame));
    ++result.frames;
  }
  // Reliable subscribers may still be receiving the last frames: let the writers drain before
  // they go (a deleted writer's unacknowledged samples are lost).
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  return result;
}

}  // namespace lrd_ros2
