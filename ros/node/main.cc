// lrdslam_ros: the ROS 1 node (see slam_node.h; parameters and topics in the README, "On a robot
// with ROS"). SIGINT (roscpp's handler) ends the spin; the node then tracks what is queued, stops
// the threads and writes the trajectory to ~output_dir.
#include <ros/ros.h>

#include "lrd/util/error.h"
#include "slam_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "lrdslam");
  ros::NodeHandle node, private_node("~");
  try {
    lrd_ros::SlamNode slam(node, private_node);
    ros::spin();
    slam.stop();
    if (slam.failed()) return 1;
  } catch (const std::exception& e) {
    ROS_FATAL("lrdslam: %s", e.what());
    return 1;
  }
  return 0;
}
