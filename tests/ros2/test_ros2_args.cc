// The ROS 2 node's command line (rcl's rules), parameter precedence, and ROS 2's name mapping.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "lrd/node/node_params.h"
#include "lrd/util/error.h"
#include "participant.h"
#include "ros_args.h"

namespace lrd_ros2 {
namespace {

RosArgs parse(std::vector<std::string> argv) {
  return parse_ros_args(argv);
}

std::filesystem::path write_file(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path;
}

TEST(RosArgs, RemapsNodeNameNamespaceAndTopics) {
  const RosArgs a = parse({"--ros-args", "-r", "__node:=slam", "-r", "__ns:=/robot1", "--remap",
                           "/camera/rgb/image_color:=/cam/color", "--", "extra"});
  EXPECT_EQ(a.node_name, "slam");
  EXPECT_EQ(a.node_namespace, "/robot1");
  EXPECT_EQ(a.remaps.at("/camera/rgb/image_color"), "/cam/color");
  ASSERT_EQ(a.other_args.size(), 1u);
  EXPECT_EQ(a.other_args[0], "extra");
}

TEST(RosArgs, UnknownFlagsAndMalformedAssignmentsAreErrors) {
  EXPECT_THROW((void)parse({"--ros-args", "--bogus"}), lrd::Error);
  EXPECT_THROW((void)parse({"--ros-args", "-p", "mode"}), lrd::Error);
  EXPECT_THROW((void)parse({"--ros-args", "-p"}), lrd::Error);
  EXPECT_THROW((void)parse({"--ros-args", "-r", "__node:=1bad"}), lrd::Error);
  EXPECT_NO_THROW((void)parse({"--ros-args", "--log-level", "debug", "-e", "/"}));
}

TEST(RosArgs, ParametersApplyInCommandLineOrderWhereTheirNodeKeyMatches) {
  const auto file = write_file("lrd_params.yaml",
                               "/**:\n  ros__parameters:\n    mode: geometric\n    queue_size: 3\n"
                               "lrdslam:\n  ros__parameters:\n    dense: true\n    camera:\n      fx: 525.0\n"
                               "other_node:\n  ros__parameters:\n    mode: static\n");
  const RosArgs a = parse({"--ros-args", "--params-file", file.string(), "-p", "mode:=full", "-p",
                           "other_node:queue_size:=9", "-p", "max_pair_dt:=0.03"});
  const ParamStore store(a, "/lrdslam");
  const lrd::node::NodeParams p = lrd::node::NodeParams::from(store);
  EXPECT_EQ(p.system.mode, "full");  // -p after the file wins
  EXPECT_EQ(p.queue_size, 3);        // other_node's value is not ours
  EXPECT_TRUE(p.system.dense);
  EXPECT_DOUBLE_EQ(p.max_pair_dt, 0.03);
  double fx = 0.0;
  store.get("camera.fx", fx);  // nested maps join with dots
  EXPECT_DOUBLE_EQ(fx, 525.0);
  EXPECT_TRUE(store.unused().empty());
}

TEST(RosArgs, WildcardAndNestedNodeKeys) {
  const auto file = write_file("lrd_params_ns.yaml",
                               "robot1:\n  lrdslam:\n    ros__parameters:\n      mode: semantic\n"
                               "/*/lrdslam:\n  ros__parameters:\n    queue_size: 7\n");
  const RosArgs a = parse({"--ros-args", "--params-file", file.string()});
  const lrd::node::NodeParams in_ns = lrd::node::NodeParams::from(ParamStore(a, "/robot1/lrdslam"));
  EXPECT_EQ(in_ns.system.mode, "semantic");
  EXPECT_EQ(in_ns.queue_size, 7);
  const lrd::node::NodeParams root = lrd::node::NodeParams::from(ParamStore(a, "/lrdslam"));
  EXPECT_EQ(root.system.mode, "");
  EXPECT_EQ(root.queue_size, 2);
}

TEST(RosArgs, WrongTypesAndBadFilesNameTheParameterOrFile) {
  const RosArgs a = parse({"--ros-args", "-p", "queue_size:=many", "-p", "nothing:=1"});
  const ParamStore store(a, "/lrdslam");
  try {
    (void)lrd::node::NodeParams::from(store);
    FAIL() << "no error";
  } catch (const lrd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("queue_size (-p queue_size): 'many' is not an integer"),
              std::string::npos)
        << e.what();
  }
  const RosArgs range = parse({"--ros-args", "-p", "queue_size:=0"});
  EXPECT_THROW((void)lrd::node::NodeParams::from(ParamStore(range, "/lrdslam")), lrd::Error);
  const auto bad = write_file("lrd_params_bad.yaml", "lrdslam:\n  ros__parameters: [1, 2\n");
  try {
    (void)parse({"--ros-args", "--params-file", bad.string()});
    FAIL() << "no error";
  } catch (const lrd::Error& e) {
    EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)parse({"--ros-args", "--params-file", "/nonexistent/p.yaml"}), lrd::Error);
  const ParamStore unused_store(a, "/lrdslam");
  int q = 0;
  EXPECT_THROW(unused_store.get("queue_size", q), lrd::Error);
  ASSERT_EQ(unused_store.unused().size(), 1u);
  EXPECT_EQ(unused_store.unused()[0], "nothing (-p nothing)");
}

TEST(Names, RosNamesMapOntoDdsAsRmwMapsThem) {
  EXPECT_EQ(dds_topic_name("/lrdslam/pose"), "rt/lrdslam/pose");
  EXPECT_EQ(dds_type_name("geometry_msgs/msg/PoseStamped"), "geometry_msgs::msg::dds_::PoseStamped_");
  EXPECT_THROW((void)dds_type_name("PoseStamped"), lrd::Error);
  EXPECT_EQ(resolve_name("/tf", "/robot1", "lrdslam"), "/tf");
  EXPECT_EQ(resolve_name("~/pose", "/robot1", "lrdslam"), "/robot1/lrdslam/pose");
  EXPECT_EQ(resolve_name("~/pose", "/", "lrdslam"), "/lrdslam/pose");
  EXPECT_EQ(resolve_name("camera/image", "/robot1", "lrdslam"), "/robot1/camera/image");
  EXPECT_EQ(parse_distro("humble"), Distro::Humble);
  EXPECT_EQ(parse_distro("jazzy"), Distro::Jazzy);
  EXPECT_THROW((void)parse_distro("foxy"), lrd::Error);
}

TEST(Names, DomainIdComesFromTheEnvironmentAndIsChecked) {
  setenv("ROS_DOMAIN_ID", "42", 1);
  setenv("ROS_LOCALHOST_ONLY", "1", 1);
  DomainSettings d = domain_from_environment();
  EXPECT_EQ(d.domain_id, 42u);
  EXPECT_TRUE(d.localhost_only);
  setenv("ROS_DOMAIN_ID", "233", 1);
  EXPECT_THROW((void)domain_from_environment(), lrd::Error);
  setenv("ROS_DOMAIN_ID", "x", 1);
  EXPECT_THROW((void)domain_from_environment(), lrd::Error);
  unsetenv("ROS_DOMAIN_ID");
  unsetenv("ROS_LOCALHOST_ONLY");
  d = domain_from_environment();
  EXPECT_EQ(d.domain_id, 0u);
  EXPECT_FALSE(d.localhost_only);
}

}  // namespace
}  // namespace lrd_ros2
