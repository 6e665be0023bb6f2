// Seeds for the fuzz harnesses, made by the project's own writers so the search starts from valid
// files: a tiny TUM folder's lists, its ROS 2 bags (MCAP and sqlite3), a PLY, a small vocabulary,
// CDR messages and image fields; settings and configs from config/. Map files come from a run
// (bench/fuzz/run.sh makes one with `lrdslam run --save-map`).
//   fuzz_make_seeds OUT_DIR CONFIG_DIR      (writes OUT_DIR/HARNESS/seed_*)
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <string>
#include <vector>

#include "lrd/dense/ply_io.h"
#include "lrd/io/tum_sequence.h"
#include "lrd/place/vocabulary.h"
#include "lrd/rosbag2/messages.h"
#include "lrd/rosbag2/rosbag2_writer.h"
#ifdef LRD_HAVE_ROS
#include "lrd_ros/bag_writer.h"
#endif

namespace fs = std::filesystem;

namespace {

void put(const fs::path& file, const std::string& bytes) {
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string read(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string bytes_of(const std::vector<std::uint8_t>& v, char selector) {
  return std::string(1, selector) + std::string(v.begin(), v.end());
}

// Four 16x12 frames with ground truth: the TUM layout at its smallest.
fs::path tiny_sequence(const fs::path& dir) {
  fs::create_directories(dir / "rgb");
  fs::create_directories(dir / "depth");
  std::string rgb = "# color images\n", depth = "# depth maps\n", gt = "# ground truth\n";
  for (int i = 0; i < 4; ++i) {
    const std::string t = std::to_string(1305031102.175304 + i * 0.033).substr(0, 17);
    cv::imwrite((dir / "rgb" / (t + ".png")).string(), cv::Mat(12, 16, CV_8UC3, cv::Scalar(40 * i, 90, 160)));
    cv::imwrite((dir / "depth" / (t + ".png")).string(),
                cv::Mat(12, 16, CV_16UC1, cv::Scalar(5000 + 100 * i)));
    rgb += t + " rgb/" + t + ".png\n";
    depth += t + " depth/" + t + ".png\n";
    gt += t + " 0.1 0.2 " + std::to_string(0.3 + 0.01 * i) + " 0 0 0 1\n";
  }
  put(dir / "rgb.txt", rgb);
  put(dir / "depth.txt", depth);
  put(dir / "groundtruth.txt", gt);
  return dir;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: fuzz_make_seeds OUT_DIR CONFIG_DIR\n");
    return 2;
  }
  try {
    const fs::path out = argv[1], config = argv[2];
    const fs::path seq = tiny_sequence(out / "tiny_sequence");
    const std::string nul(1, '\0');
    put(out / "tum_lists" / "seed_lists",
        read(seq / "rgb.txt") + nul + read(seq / "depth.txt") + nul + nul + read(seq / "groundtruth.txt"));
    put(out / "tum_lists" / "seed_associations",
        read(seq / "rgb.txt") + nul + read(seq / "depth.txt") + nul +
            "1305031102.175304 rgb/a.png 1305031102.175304 depth/a.png\n" + nul +
            read(seq / "groundtruth.txt"));
    for (const auto& e : fs::directory_iterator(config))
      if (e.path().extension() == ".yaml") {
        const bool settings = read(e.path()).rfind("%YAML", 0) == 0;
        put(out / (settings ? "orbslam_settings" : "yaml_config") / ("seed_" + e.path().filename().string()),
            read(e.path()));
      }

    lrd::camera::PinholeCamera camera;
    camera.width = 16;
    camera.height = 12;
    camera.fx = camera.fy = 12.0;
    camera.cx = 8.0;
    camera.cy = 6.0;
    const lrd::io::TumSequence tum = lrd::io::TumSequence::open(seq);
    lrd::rosbag2::write_rosbag2(tum, camera, out / "tmp.mcap");
    put(out / "rosbag2" / "seed_mcap", std::string(1, '\0') + read(out / "tmp.mcap"));
    lrd::rosbag2::write_rosbag2(tum, camera, out / "tmp.db3");
    put(out / "rosbag2" / "seed_db3", std::string(1, '\1') + read(out / "tmp.db3"));
#ifdef LRD_HAVE_ROS
    lrd_ros::write_bag(tum, camera, out / "tmp.bag");
    put(out / "rosbag1" / "seed_bag", read(out / "tmp.bag"));
    fs::remove(out / "tmp.bag");
#endif
    fs::remove(out / "tmp.mcap");
    fs::remove(out / "tmp.db3");
    fs::remove(out / "metadata.yaml");

    lrd::dense::PointCloud cloud;
    for (int i = 0; i < 5; ++i) {
      cloud.points.emplace_back(0.1f * i, 0.2f, 1.0f);
      cloud.colours.emplace_back(10 * i, 20, 30);
    }
    fs::create_directories(out / "ply");
    lrd::dense::write_ply(out / "ply" / "seed_binary", cloud);
    put(out / "ply" / "seed_ascii",
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
        "end_header\n0 0 1\n0.5 0.25 2\n");

    std::mt19937 rng(7);
    std::vector<cv::Mat> descriptors;
    for (int img = 0; img < 3; ++img) {
      cv::Mat d(40, 32, CV_8UC1);
      for (int r = 0; r < d.rows; ++r)
        for (int c = 0; c < d.cols; ++c) d.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(rng());
      descriptors.push_back(d);
    }
    lrd::place::VocabularyParams vp;
    vp.k = 3;
    vp.levels = 2;
    fs::create_directories(out / "vocabulary");
    lrd::place::Vocabulary::train(descriptors, vp).save(out / "vocabulary" / "seed_small");

    namespace msg = lrd::rosbag2::msg;
    msg::Image image;
    image.header.frame_id = "camera";
    image.width = 2;
    image.height = 2;
    image.encoding = "rgb8";
    image.step = 6;
    image.data.assign(12, 7);
    put(out / "cdr_messages" / "seed_image", bytes_of(msg::encode(image), 0));
    msg::CameraInfo info;
    info.width = 16;
    info.height = 12;
    info.distortion_model = "plumb_bob";
    info.d = {0, 0, 0, 0, 0};
    info.k = {12, 0, 8, 0, 12, 6, 0, 0, 1};
    put(out / "cdr_messages" / "seed_camera_info", bytes_of(msg::encode(info), 1));
    msg::TFMessage tf;
    tf.transforms.resize(1);
    tf.transforms[0].header.frame_id = "/world";
    tf.transforms[0].child_frame_id = "/kinect";
    put(out / "cdr_messages" / "seed_tf", bytes_of(msg::encode(tf), 2));

    // width 2, height 2, step 6, little-endian, rgb8; camera 16x12 plumb_bob, 5 coefficients, K.
    std::string fields = {2, 0, 2, 0, 6, 0, 0, 0, 0, 0, 16, 0, 12, 0, 0, 5};
    for (int i = 0; i < 5 + 9; ++i) {
      const double v = i >= 5 ? (i == 5 || i == 9 ? 12.0 : i == 13 ? 1.0 : 0.0) : 0.0;
      fields.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
    put(out / "image_messages" / "seed_rgb8", fields + std::string(12, '\x50'));
    std::printf("fuzz_make_seeds: seeds in %s\n", out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_make_seeds: %s\n", e.what());
    return 1;
  }
  return 0;
}
