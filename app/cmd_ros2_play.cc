// `lrdslam ros2-play`: a sequence folder or a bag published over ROS 2 (DDS) as a camera driver
// and a TUM bag's /tf publish it (ros2/play/ros2_player.h), at the camera's pace times --rate.
#include <fmt/format.h>

#include <memory>
#include <string>

#include "app/bag_input.h"
#include "app/commands.h"
#include "lrd/config/orbslam_settings.h"
#include "lrd/io/tum_sequence.h"
#include "lrd/runner/sequence_runner.h"
#include "lrd/util/error.h"
#ifdef LRD_HAVE_ROS2
#include "ros2_player.h"
#endif

namespace lrd::app {

namespace {

struct Ros2PlayCli {
  std::string sequence;
  BagCli bag;
  double rate = 1.0;
  double wait_s = 20.0;
  std::size_t frames = 0;
  bool reliable = false;
};

#ifdef LRD_HAVE_ROS2
void play(const Ros2PlayCli& cli) {
  std::shared_ptr<const io::FrameSource> source;
  camera::PinholeCamera camera;
  if (!cli.sequence.empty()) {
    source = std::make_shared<io::TumSequence>(io::TumSequence::open(cli.sequence));
    camera = config::read_orbslam_settings(std::filesystem::path(cli.sequence) / "settings.yaml").camera;
  } else {
    source = open_bag(cli.bag);
    if (!source->camera())
      throw Error(fmt::format("{}: no camera_info on {}", cli.bag.bag, cli.bag.camera_info_topic));
    camera = runner::camera_from_source(*source->camera(), camera);
  }
  lrd_ros2::PlayOptions o;
  o.layout.topics.rgb = cli.bag.rgb_topic;
  o.layout.topics.depth = cli.bag.depth_topic;
  o.layout.topics.camera_info = cli.bag.camera_info_topic;
  o.rate = cli.rate;
  o.wait_s = cli.wait_s;
  o.max_frames = cli.frames;
  o.reliable = cli.reliable;
  o.depth_factor = camera.depth_map_factor;
  const lrd_ros2::PlayResult r = lrd_ros2::play(*source, camera, o);
  fmt::print("ros2-play: {} frames published on {} and {}{}\n", r.frames, o.layout.topics.rgb,
             o.layout.topics.depth,
             r.subscriber_seen ? "" : fmt::format(" (no subscriber within {} s)", cli.wait_s));
}
#else
void play(const Ros2PlayCli& /*cli*/) {
  throw Error(
      "ros2-play: this build has no ROS 2 (Cyclone DDS: scripts/install-deps.sh installs cyclonedds-dev)");
}
#endif

}  // namespace

void register_ros2_play_command(CLI::App& app) {
  auto cli = std::make_shared<Ros2PlayCli>();
  CLI::App* cmd = app.add_subcommand(
      "ros2-play",
      "Publish a sequence folder or a bag over ROS 2 (DDS), as a camera driver and a TUM bag's /tf do");
  auto* sequence =
      cmd->add_option("--sequence", cli->sequence, "TUM-layout sequence folder (with settings.yaml)");
  auto* bag = cmd->add_option("--bag", cli->bag.bag, "A ROS 1 or ROS 2 bag in the TUM RGB-D layout")
                  ->excludes(sequence);
  cmd->add_option("--rate", cli->rate, "Times the camera's pace")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  cmd->add_option("--frames", cli->frames, "Publish only the first N frames")->check(CLI::PositiveNumber);
  cmd->add_option("--wait", cli->wait_s, "Seconds to wait for a subscriber before the first frame")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  cmd->add_flag("--reliable", cli->reliable, "Images reliable (default: the sensor-data QoS, best effort)");
  cmd->add_option("--rgb-topic", cli->bag.rgb_topic, "Colour images' topic (read from the bag and published)")
      ->capture_default_str();
  cmd->add_option("--depth-topic", cli->bag.depth_topic, "Depth images' topic")->capture_default_str();
  cmd->add_option("--camera-info-topic", cli->bag.camera_info_topic, "The colour camera_info topic")
      ->capture_default_str();
  cmd->add_option("--gt-from-tf", cli->bag.gt_from_tf,
                  "With --bag: ground truth = CHILD's pose in PARENT on /tf")
      ->needs(bag);
  cmd->callback([cli] {
    if (cli->sequence.empty() && cli->bag.bag.empty())
      throw Error("ros2-play: give --sequence FOLDER or --bag FILE");
    play(*cli);
  });
}

}  // namespace lrd::app
