// lrdslam_ros2: the ROS 2 node (see ros2_node.h; parameters, topics and QoS in docs/ros2.md).
//   lrdslam_ros2 --ros-args -r __node:=lrdslam -p mode:=full [--params-file FILE.yaml]
// SIGINT or SIGTERM ends it: the node tracks what is queued, stops the threads and writes the
// trajectory and node_summary.json to output_dir.
#include <fmt/format.h>
#include <pthread.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <string>
#include <vector>

#include "lrd/util/error.h"
#include "ros2_node.h"
#include "ros_args.h"

int main(int argc, char** argv) {
  // The signals wait for sigwait below: blocked before any thread (DDS's, the node's) starts.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGUSR1);  // the node's own "cannot go on"
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  try {
    const lrd_ros2::RosArgs args = lrd_ros2::parse_ros_args(std::vector<std::string>(argv + 1, argv + argc));
    if (!args.other_args.empty())
      throw lrd::Error(fmt::format("unexpected argument '{}': give parameters as --ros-args -p name:=value",
                                   args.other_args.front()));
    lrd_ros2::Ros2Node node(args, [] { kill(getpid(), SIGUSR1); });
    int signal = 0;
    sigwait(&stop_signals, &signal);
    node.stop();
    if (node.failed()) return 1;
  } catch (const std::exception& e) {
    lrd_ros2::log_line("FATAL", "lrdslam", e.what());
    return 1;
  }
  return 0;
}
