// Tracks a TUM-layout sequence with lrd::System and writes its trajectory:
//   minimal_slam SEQUENCE_DIR OUT_TRAJECTORY
#include <cstdio>
#include <exception>
#include <opencv2/imgproc.hpp>

#include "lrd/io/tum_sequence.h"
#include "lrd/system.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s SEQUENCE_DIR OUT_TRAJECTORY\n", argv[0]);
    return 2;
  }
  try {
    const auto sequence = lrd::io::TumSequence::open(argv[1]);
    lrd::config::Config config;  // defaults: TUM fr3 camera, 1000 ORB features
    lrd::System slam(config);
    std::size_t ok = 0;
    for (std::size_t i = 0; i < sequence.size(); ++i) {
      const auto frame = sequence.load_rgbd(i, config.camera.depth_map_factor);
      // The loader gives BGR; the TUM presets say RGB, so tell the system about the swap.
      cv::Mat rgb;
      cv::cvtColor(frame.rgb, rgb, cv::COLOR_BGR2RGB);
      const auto result = slam.track_rgbd(rgb, frame.depth, frame.timestamp);
      ok += result.state == lrd::TrackingState::Ok;
    }
    slam.shutdown();
    slam.save_trajectory_tum(argv[2]);
    std::printf("%zu of %zu frames tracked\n", ok, sequence.size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
