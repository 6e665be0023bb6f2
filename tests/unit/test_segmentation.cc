// Segmentation without a network: the `masks` backend (timestamp-named PNGs), the `segmentation`
// config section, and the segmentation thread's sync and async schedules with a fake segmenter.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <thread>

#include "error_of.h"
#include "lrd/config/config.h"
#include "lrd/segmentation/mask_folder_segmenter.h"
#include "lrd/segmentation/segmentation_params.h"
#include "lrd/segmentation/segmentation_worker.h"
#include "lrd/util/error.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using lrd::segmentation::MaskFolderParams;
using lrd::segmentation::MaskFolderSegmenter;
using lrd::segmentation::Schedule;
using lrd::segmentation::SegmentationParams;
using lrd::segmentation::SegmentationResult;
using lrd::segmentation::SegmentationWorker;
using lrd::segmentation::Segmenter;

namespace {

constexpr int kW = 8, kH = 6;

// A kW x kH mask whose pixel (0, 0) is `tag` (to tell files apart) and whose pixels hold the values
// 0, 1, 2, 13, 15, 255 in turn elsewhere.
cv::Mat tagged_mask(int tag) {
  cv::Mat m(kH, kW, CV_8UC1);
  const int values[] = {0, 1, 2, 13, 15, 255};
  for (int i = 0; i < kW * kH; ++i) m.data[i] = static_cast<std::uint8_t>(values[i % 6]);
  m.at<std::uint8_t>(0, 0) = static_cast<std::uint8_t>(tag);
  return m;
}

void write_png(const fs::path& file, const cv::Mat& img) {
  ASSERT_TRUE(cv::imwrite(file.string(), img)) << file;
}

using lrd::test::error_of;

const cv::Mat& image() {
  static const cv::Mat rgb(kH, kW, CV_8UC3, cv::Scalar(10, 20, 30));
  return rgb;
}

struct MaskFolder {
  lrd::test::TempDir tmp{"masks"};
  MaskFolder() {
    write_png(tmp.path() / "1305031102.175304.png", tagged_mask(101));
    write_png(tmp.path() / "1305031102.211700.png", tagged_mask(102));
    write_png(tmp.path() / "1305031102.243600.png", tagged_mask(103));
    // Not timestamp names: ignored.
    write_png(tmp.path() / "overview.png", tagged_mask(7));
    write_png(tmp.path() / "1305031102.3x.png", tagged_mask(8));
    tmp.write("1305031103.000000.txt", "not a mask");
  }
  [[nodiscard]] MaskFolderParams params(double tolerance = 0.002, std::vector<int> values = {}) const {
    MaskFolderParams p;
    p.folder = tmp.path();
    p.max_time_difference = tolerance;
    p.dynamic_values = std::move(values);
    return p;
  }
};

}  // namespace

TEST(MaskFolderSegmenter, IndexesOnlyTimestampNamedPngs) {
  MaskFolder f;
  MaskFolderSegmenter seg(f.params());
  EXPECT_EQ(seg.size(), 3u);
  EXPECT_NE(seg.describe().find(f.tmp.path().string()), std::string::npos) << seg.describe();
  EXPECT_EQ(seg.describe().rfind("masks (", 0), 0u) << seg.describe();
}

TEST(MaskFolderSegmenter, TakesTheNearestMaskWithinTheTolerance) {
  MaskFolder f;
  // With the default tolerance (2 ms) each frame finds its own file.
  MaskFolderSegmenter exact(f.params());
  // Any nonzero value is dynamic, so the tag pixel (0, 0) is 255 for every file; the files are told
  // apart with a wide tolerance below.
  EXPECT_EQ(exact.segment(image(), true, 1305031102.175304).at<std::uint8_t>(0, 0), 255);
  EXPECT_NO_THROW((void)exact.segment(image(), true, 1305031102.2117 + 0.0019));
  EXPECT_NO_THROW((void)exact.segment(image(), true, 1305031102.2436 - 0.0019));

  // Tag values tell which file was taken: dynamic_values = {tag} turns only that file's pixel (0,0) on.
  auto taken = [&](double t) {
    for (int tag : {101, 102, 103}) {
      MaskFolderSegmenter s(f.params(0.05, {tag}));
      if (s.segment(image(), true, t).at<std::uint8_t>(0, 0) == 255) return tag;
    }
    return 0;
  };
  EXPECT_EQ(taken(1305031102.150), 101);  // before the first
  EXPECT_EQ(taken(1305031102.175304), 101);
  EXPECT_EQ(taken(1305031102.192), 101);  // 16.7 ms after the first, 19.7 ms before the second
  EXPECT_EQ(taken(1305031102.195), 102);  // 19.7 ms after, 16.7 ms before
  EXPECT_EQ(taken(1305031102.230), 103);  // 18.3 ms after the second, 13.6 ms before the third
  EXPECT_EQ(taken(1305031102.280), 103);  // after the last
}

TEST(MaskFolderSegmenter, DynamicValuesSelectThePixels) {
  MaskFolder f;
  const cv::Mat raw = tagged_mask(101);
  auto check = [&](const std::vector<int>& values, auto is_dynamic) {
    MaskFolderSegmenter seg(f.params(0.002, values));
    const cv::Mat m = seg.segment(image(), false, 1305031102.175304);
    ASSERT_EQ(m.type(), CV_8UC1);
    ASSERT_EQ(m.size(), raw.size());
    for (int i = 0; i < kW * kH; ++i)
      EXPECT_EQ(m.data[i], is_dynamic(raw.data[i]) ? 255 : 0) << "value " << int(raw.data[i]);
  };
  check({}, [](int v) { return v != 0; });
  check({15}, [](int v) { return v == 15; });
  check({13, 15, 255}, [](int v) { return v == 13 || v == 15 || v == 255; });
  check({0}, [](int v) { return v == 0; });
  check({-1, 300}, [](int) { return false; });  // out of range: nothing
}

TEST(MaskFolderSegmenter, MissingOrEmptyFolderIsAnErrorNamingIt) {
  lrd::test::TempDir tmp("masks_err");
  MaskFolderParams p;
  p.folder = tmp.path() / "no_such_folder";
  std::string msg = error_of([&] { MaskFolderSegmenter s(p); });
  EXPECT_NE(msg.find(p.folder.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("not found"), std::string::npos) << msg;

  p.folder = tmp.path() / "empty";
  fs::create_directories(p.folder);
  tmp.write("empty/readme.txt", "no masks here");
  write_png(p.folder / "mask.png", tagged_mask(1));
  msg = error_of([&] { MaskFolderSegmenter s(p); });
  EXPECT_NE(msg.find(p.folder.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("no timestamp-named"), std::string::npos) << msg;

  p.folder.clear();
  msg = error_of([&] { MaskFolderSegmenter s(p); });
  EXPECT_NE(msg.find("segmentation.masks.folder"), std::string::npos) << msg;
}

TEST(MaskFolderSegmenter, NoMaskNearTheFrameNamesFolderAndTimestamp) {
  MaskFolder f;
  MaskFolderSegmenter seg(f.params());
  const std::string msg = error_of([&] { (void)seg.segment(image(), true, 1305031102.5); });
  EXPECT_NE(msg.find(f.tmp.path().string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("1305031102.500000"), std::string::npos) << msg;
  EXPECT_NE(msg.find("1305031102.243600.png"), std::string::npos) << msg;  // the nearest one
  // Just outside the tolerance on either side.
  EXPECT_THROW((void)seg.segment(image(), true, 1305031102.175304 - 0.0021), lrd::Error);
  EXPECT_THROW((void)seg.segment(image(), true, 1305031102.175304 + 0.0021), lrd::Error);
}

TEST(MaskFolderSegmenter, WrongTypeSizeOrUnreadableFileIsAnErrorNamingIt) {
  lrd::test::TempDir tmp("masks_bad");
  const fs::path deep = tmp.path() / "1.000000.png", colour = tmp.path() / "2.000000.png",
                 small = tmp.path() / "3.000000.png", broken = tmp.path() / "4.000000.png";
  write_png(deep, cv::Mat(kH, kW, CV_16UC1, cv::Scalar(1000)));
  write_png(colour, cv::Mat(kH, kW, CV_8UC3, cv::Scalar(0, 0, 255)));
  write_png(small, cv::Mat(kH - 1, kW, CV_8UC1, cv::Scalar(255)));
  tmp.write("4.000000.png", "this is not a PNG");
  MaskFolderParams p;
  p.folder = tmp.path();
  MaskFolderSegmenter seg(p);
  ASSERT_EQ(seg.size(), 4u);

  std::string msg = error_of([&] { (void)seg.segment(image(), true, 1.0); });
  EXPECT_NE(msg.find(deep.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("8-bit single-channel"), std::string::npos) << msg;
  EXPECT_NE(msg.find("CV_16UC1"), std::string::npos) << msg;

  msg = error_of([&] { (void)seg.segment(image(), true, 2.0); });
  EXPECT_NE(msg.find(colour.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("CV_8UC3"), std::string::npos) << msg;

  msg = error_of([&] { (void)seg.segment(image(), true, 3.0); });
  EXPECT_NE(msg.find(small.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("8x5"), std::string::npos) << msg;
  EXPECT_NE(msg.find("8x6"), std::string::npos) << msg;

  msg = error_of([&] { (void)seg.segment(image(), true, 4.0); });
  EXPECT_NE(msg.find(broken.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("cannot decode image"), std::string::npos) << msg;
}

// --- the `segmentation` config section

namespace {

struct ConfigFile {
  lrd::test::TempDir tmp{"seg_config"};
  // Parses `text` (a whole config file) and reads its segmentation section.
  SegmentationParams read(const std::string& text) const {
    const fs::path file = tmp.write("config.yaml", text);
    const lrd::config::Config cfg = lrd::config::load_config(file);
    return SegmentationParams::from_config(cfg.segmentation, file.parent_path());
  }
  std::string error(const std::string& text) const {
    return error_of([&] { (void)read(text); });
  }
};

}  // namespace

TEST(SegmentationParams, DefaultsWithoutASection) {
  ConfigFile c;
  const SegmentationParams p = c.read("features:\n  n_features: 1000\n");
  EXPECT_EQ(p.backend, lrd::segmentation::Backend::None);
  EXPECT_EQ(p.schedule, Schedule::Async);
  EXPECT_DOUBLE_EQ(p.max_wait_ms, 0.0);  // never wait: measured fastest on 2 cores
  EXPECT_EQ(p.stride, 2);                // the network on every second frame
  EXPECT_EQ(p.dilation_px, 7);
  EXPECT_EQ(p.onnx.output, lrd::segmentation::OutputLayout::Logits);
  EXPECT_EQ(p.onnx.classes, lrd::segmentation::voc_classes());
  ASSERT_EQ(p.onnx.classes.size(), 21u);
  EXPECT_EQ(p.onnx.classes[15], "person");
  // person, bird, cat, cow, dog, horse, sheep
  EXPECT_EQ(p.onnx.dynamic_ids, (std::vector<int>{15, 3, 8, 10, 12, 13, 17}));
  EXPECT_TRUE(p.masks.folder.empty());
  EXPECT_TRUE(p.masks.dynamic_values.empty());
  EXPECT_DOUBLE_EQ(p.masks.max_time_difference, 0.002);
  EXPECT_EQ(lrd::segmentation::to_string(p.backend), "none");
  EXPECT_EQ(lrd::segmentation::to_string(p.schedule), "async");
}

TEST(SegmentationParams, ReadsEveryKeyAndResolvesPathsAgainstTheConfigFolder) {
  ConfigFile c;
  c.tmp.write("models/net.onnx", "placeholder");
  const SegmentationParams p = c.read(
      "segmentation:\n"
      "  backend: onnx\n"
      "  schedule: sync\n"
      "  max_wait_ms: 25.5\n"
      "  dilation_px: 5\n"
      "  age_dilation_px: 2.5\n"
      "  max_age_dilation_px: 12\n"
      "  onnx:\n"
      "    model: models/net.onnx\n"
      "    input_width: 384\n"
      "    input_height: 288\n"
      "    scale: 0.00392156862745098\n"
      "    mean: [0.485, 0.456, 0.406]\n"
      "    std: [0.229, 0.224, 0.225]\n"
      "    input_order: bgr\n"
      "    output: logits\n"
      "    dynamic_classes: [horse, person]\n"
      "  masks:\n"
      "    folder: not_there/masks\n"
      "    dynamic_values: [15, 13]\n"
      "    max_time_difference: 0.01\n");
  EXPECT_EQ(p.backend, lrd::segmentation::Backend::Onnx);
  EXPECT_EQ(p.schedule, Schedule::Sync);
  EXPECT_DOUBLE_EQ(p.max_wait_ms, 25.5);
  EXPECT_EQ(p.dilation_px, 5);
  EXPECT_DOUBLE_EQ(p.age_dilation_px, 2.5);
  EXPECT_EQ(p.max_age_dilation_px, 12);
  EXPECT_EQ(p.onnx.model, c.tmp.path() / "models/net.onnx");  // exists next to the config
  EXPECT_EQ(p.onnx.input_width, 384);
  EXPECT_EQ(p.onnx.input_height, 288);
  EXPECT_NEAR(p.onnx.scale, 1.0 / 255.0, 1e-15);
  EXPECT_EQ(p.onnx.mean, (std::vector<double>{0.485, 0.456, 0.406}));
  EXPECT_EQ(p.onnx.std, (std::vector<double>{0.229, 0.224, 0.225}));
  EXPECT_FALSE(p.onnx.input_rgb);
  EXPECT_EQ(p.onnx.dynamic_classes, (std::vector<std::string>{"horse", "person"}));
  EXPECT_EQ(p.onnx.dynamic_ids, (std::vector<int>{13, 15}));
  EXPECT_EQ(p.masks.folder, fs::path("not_there/masks"));  // not next to the config: as written
  EXPECT_EQ(p.masks.dynamic_values, (std::vector<int>{15, 13}));
  EXPECT_DOUBLE_EQ(p.masks.max_time_difference, 0.01);
  EXPECT_EQ(lrd::segmentation::to_string(p.backend), "onnx");
  EXPECT_EQ(lrd::segmentation::to_string(p.schedule), "sync");
}

TEST(SegmentationParams, OwnClassesAndProbabilityLayout) {
  ConfigFile c;
  SegmentationParams p = c.read(
      "segmentation:\n  backend: masks\n  onnx:\n    classes: [bg, car, walker]\n"
      "    dynamic_classes: [walker]\n    output: labels\n");
  EXPECT_EQ(p.backend, lrd::segmentation::Backend::Masks);
  EXPECT_EQ(p.onnx.output, lrd::segmentation::OutputLayout::Labels);
  EXPECT_EQ(p.onnx.dynamic_ids, (std::vector<int>{2}));
  p = c.read("segmentation:\n  onnx:\n    output: probability\n    threshold: 0.3\n");
  EXPECT_EQ(p.onnx.output, lrd::segmentation::OutputLayout::Probability);
  EXPECT_DOUBLE_EQ(p.onnx.threshold, 0.3);
  EXPECT_EQ(p.onnx.dynamic_ids, (std::vector<int>{0}));
}

TEST(SegmentationParams, TyposAndBadValuesAreErrors) {
  ConfigFile c;
  std::string msg = c.error("segmentation:\n  backend: onnx\n  dilaton_px: 3\n");
  EXPECT_NE(msg.find("segmentation.dilaton_px"), std::string::npos) << msg;
  EXPECT_NE(msg.find("config.yaml"), std::string::npos) << msg;

  msg = c.error("segmentation:\n  onnx:\n    modle: x.onnx\n");
  EXPECT_NE(msg.find("segmentation.onnx.modle"), std::string::npos) << msg;

  msg = c.error("segmentation:\n  masks:\n    max_time_diff: 0.1\n");
  EXPECT_NE(msg.find("segmentation.masks.max_time_diff"), std::string::npos) << msg;

  msg = c.error("segmentation:\n  onnx:\n    dynamic_classes: [person, unicorn]\n");
  EXPECT_NE(msg.find("segmentation.onnx.dynamic_classes"), std::string::npos) << msg;
  EXPECT_NE(msg.find("unicorn"), std::string::npos) << msg;

  msg = c.error("segmentation:\n  backend: tensorrt\n");
  EXPECT_NE(msg.find("segmentation.backend"), std::string::npos) << msg;
  EXPECT_NE(msg.find("tensorrt"), std::string::npos) << msg;
  EXPECT_NE(msg.find("onnx"), std::string::npos) << msg;

  msg = c.error("segmentation:\n  schedule: sometimes\n");
  EXPECT_NE(msg.find("segmentation.schedule"), std::string::npos) << msg;

  msg = c.error("segmentation:\n  onnx:\n    mean: [0.5, 0.5]\n");
  EXPECT_NE(msg.find("segmentation.onnx.mean"), std::string::npos) << msg;
  msg = c.error("segmentation:\n  onnx:\n    std: [0.5, 0.0, 0.5]\n");
  EXPECT_NE(msg.find("segmentation.onnx.std"), std::string::npos) << msg;
  msg = c.error("segmentation:\n  onnx:\n    input_order: rbg\n");
  EXPECT_NE(msg.find("segmentation.onnx.input_order"), std::string::npos) << msg;
  msg = c.error("segmentation:\n  onnx:\n    threshold: 1.5\n");
  EXPECT_NE(msg.find("segmentation.onnx.threshold"), std::string::npos) << msg;
  msg = c.error("segmentation:\n  dilation_px: -1\n");
  EXPECT_NE(msg.find("segmentation.dilation_px"), std::string::npos) << msg;
  msg = c.error("segmentation:\n  max_wait_ms: fast\n");
  EXPECT_NE(msg.find("segmentation.max_wait_ms"), std::string::npos) << msg;
}

// --- the segmentation thread

namespace {

// Sleeps `delay_ms`, then returns a mask filled with the frame's timestamp (frames are submitted
// with timestamp = id); throws at timestamp `fail_at`.
class FakeSegmenter : public Segmenter {
 public:
  explicit FakeSegmenter(int delay_ms, double fail_at = -1.0) : delay_ms_(delay_ms), fail_at_(fail_at) {}
  cv::Mat segment(const cv::Mat& rgb, bool rgb_order, double timestamp) override {
    started.fetch_add(1);
    EXPECT_FALSE(rgb_order);
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms_));
    if (timestamp == fail_at_)
      throw lrd::Error("fake segmenter: no mask for frame " + std::to_string(timestamp));
    finished.fetch_add(1);
    return cv::Mat(rgb.size(), CV_8UC1, cv::Scalar(static_cast<int>(timestamp)));
  }
  std::string describe() const override { return "fake"; }

  std::atomic<int> started{0}, finished{0};

 private:
  int delay_ms_;
  double fail_at_;
};

struct Worker {
  FakeSegmenter* fake;  // owned by the worker
  std::unique_ptr<SegmentationWorker> worker;
  Worker(int delay_ms, Schedule schedule, double fail_at = -1.0) {
    auto seg = std::make_unique<FakeSegmenter>(delay_ms, fail_at);
    fake = seg.get();
    worker = std::make_unique<SegmentationWorker>(std::move(seg), schedule, false);
  }
  void submit(std::uint64_t id) const { worker->submit(id, static_cast<double>(id), image()); }
};

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

int tag(const SegmentationResult& r) {
  return r.mask.at<std::uint8_t>(0, 0);
}

}  // namespace

TEST(SegmentationWorker, SyncGivesEachFrameItsOwnMask) {
  Worker w(3, Schedule::Sync);
  EXPECT_EQ(w.worker->schedule(), Schedule::Sync);
  EXPECT_EQ(w.worker->segmenter().describe(), "fake");
  for (std::uint64_t id = 0; id < 8; ++id) {
    w.submit(id);
    const auto r = w.worker->wait(id, std::nullopt);
    ASSERT_TRUE(r.has_value());
    EXPECT_EQ(r->frame_id, id);
    EXPECT_DOUBLE_EQ(r->timestamp, static_cast<double>(id));
    EXPECT_EQ(tag(*r), static_cast<int>(id));
    EXPECT_EQ(r->mask.size(), image().size());
    EXPECT_GE(r->seconds, 0.002);
  }
  EXPECT_EQ(w.worker->skipped(), 0u);
  EXPECT_EQ(w.fake->finished.load(), 8);
}

TEST(SegmentationWorker, SyncKeepsEveryQueuedRequest) {
  Worker w(5, Schedule::Sync);
  for (std::uint64_t id = 0; id < 5; ++id) w.submit(id);
  const auto r = w.worker->wait(4, std::nullopt);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->frame_id, 4u);
  EXPECT_EQ(tag(*r), 4);
  EXPECT_EQ(w.fake->finished.load(), 5);  // none skipped
  EXPECT_EQ(w.worker->skipped(), 0u);
}

TEST(SegmentationWorker, AsyncReturnsWithinTheTimeoutWithAnOlderMask) {
  Worker w(150, Schedule::Async);
  w.submit(0);
  auto t0 = std::chrono::steady_clock::now();
  auto r = w.worker->wait(0, 0.01);
  EXPECT_LT(since(t0), 0.5);    // not the 150 ms the segmenter takes (checked by the value)
  EXPECT_FALSE(r.has_value());  // nothing finished yet
  r = w.worker->wait(0, std::nullopt);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->frame_id, 0u);

  // Frame 1 keeps the segmenter busy; 2 and 3 are replaced by 4 before it is free.
  w.submit(1);
  while (w.fake->started.load() < 2) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  w.submit(2);
  w.submit(3);
  w.submit(4);
  EXPECT_EQ(w.worker->skipped(), 2u);
  t0 = std::chrono::steady_clock::now();
  r = w.worker->wait(4, 0.02);
  const double waited = since(t0);
  EXPECT_GE(waited, 0.015);
  EXPECT_LT(waited, 0.5);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->frame_id, 0u);  // the newest finished one
  EXPECT_EQ(tag(*r), 0);

  r = w.worker->wait(4, std::nullopt);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->frame_id, 4u);
  EXPECT_EQ(tag(*r), 4);
  EXPECT_EQ(w.fake->finished.load(), 3);  // frames 0, 1 and 4
  EXPECT_EQ(w.worker->skipped(), 2u);

  // A finished frame's mask is returned at once, whatever the timeout.
  t0 = std::chrono::steady_clock::now();
  r = w.worker->wait(4, 5.0);
  EXPECT_LT(since(t0), 0.5);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->frame_id, 4u);
}

TEST(SegmentationWorker, SegmenterErrorIsRethrownFromWait) {
  Worker w(2, Schedule::Sync, 2.0);
  for (std::uint64_t id = 0; id < 2; ++id) {
    w.submit(id);
    const auto r = w.worker->wait(id, std::nullopt);
    ASSERT_TRUE(r.has_value());
    EXPECT_EQ(r->frame_id, id);
  }
  w.submit(2);
  w.submit(3);
  const std::string msg = error_of([&] { (void)w.worker->wait(2, std::nullopt); });
  EXPECT_NE(msg.find("no mask for frame 2"), std::string::npos) << msg;
  // The error stays: later waits (even with a timeout) throw it too, without blocking.
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_THROW((void)w.worker->wait(3, 10.0), lrd::Error);
  EXPECT_LT(since(t0), 1.0);
  w.worker->shutdown();
}

TEST(SegmentationWorker, ShutdownWithPendingRequestsDoesNotHang) {
  const auto t0 = std::chrono::steady_clock::now();
  {
    Worker w(60, Schedule::Sync);
    for (std::uint64_t id = 0; id < 20; ++id) w.submit(id);
    while (w.fake->started.load() < 1) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    // A waiter blocked without timeout is released by shutdown.
    std::optional<SegmentationResult> waited;
    std::thread waiter([&] { waited = w.worker->wait(19, std::nullopt); });
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    w.worker->shutdown();
    waiter.join();
    EXPECT_LE(w.fake->started.load(), 3);  // the queue was not worked off
    if (waited) {
      EXPECT_LT(waited->frame_id, 19u);
    }
    // After shutdown, wait returns at once.
    const auto t1 = std::chrono::steady_clock::now();
    (void)w.worker->wait(19, std::nullopt);
    EXPECT_LT(since(t1), 0.5);
    w.worker->shutdown();  // twice is fine
  }
  {
    Worker w(60, Schedule::Async);
    for (std::uint64_t id = 0; id < 5; ++id) w.submit(id);
    // destroyed with a request pending
  }
  EXPECT_LT(since(t0), 2.0);
}
