// ROS 2 bags' building blocks: CDR as rosidl lays messages out, MCAP and sqlite3 storage written
// and read back, and every broken file an lrd::Error of one line naming it.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "error_of.h"
#include "lrd/rosbag2/mcap_reader.h"
#include "lrd/rosbag2/mcap_records.h"
#include "lrd/rosbag2/mcap_writer.h"
#include "lrd/rosbag2/messages.h"
#include "lrd/rosbag2/sqlite_bag.h"
#include "temp_dir.h"

namespace lrd::rosbag2 {
namespace {

using test::error_of;
using test::TempDir;
namespace fs = std::filesystem;

msg::Header header_of(std::int32_t sec, std::uint32_t nanosec, const std::string& frame) {
  return {{sec, nanosec}, frame};
}

std::vector<std::uint8_t> bytes_of(const std::string& hex_free) {
  return {hex_free.begin(), hex_free.end()};
}

TEST(Cdr, ImageBytesAreLaidOutAsRosidlDoes) {
  msg::Image m;
  m.header = header_of(1, 2, "a");
  m.height = 1;
  m.width = 2;
  m.encoding = "mono8";
  m.step = 2;
  m.data = {7, 9};
  const std::vector<std::uint8_t> expected = {
      0, 1, 0, 0,                              // encapsulation: CDR little-endian
      1, 0, 0, 0, 2,   0,   0,   0,            // stamp
      2, 0, 0, 0, 'a', 0,   0,   0,            // frame_id "a" + NUL, padded to 4
      1, 0, 0, 0, 2,   0,   0,   0,            // height, width
      6, 0, 0, 0, 'm', 'o', 'n', 'o', '8', 0,  // encoding
      0,                                       // is_bigendian
      0,                                       // pad to 4
      2, 0, 0, 0,                              // step
      2, 0, 0, 0, 7,   9};                     // data
  EXPECT_EQ(msg::encode(m), expected);
  const msg::Image back = msg::decode_image(expected.data(), expected.size());
  EXPECT_EQ(back.header.stamp.sec, 1);
  EXPECT_EQ(back.header.stamp.nanosec, 2u);
  EXPECT_EQ(back.header.frame_id, "a");
  EXPECT_EQ(back.encoding, "mono8");
  EXPECT_EQ(back.step, 2u);
  EXPECT_EQ(back.data, (std::vector<std::uint8_t>{7, 9}));
}

TEST(Cdr, CameraInfoRoundTripsWithEightByteAlignment) {
  msg::CameraInfo m;
  m.header = header_of(-3, 999999999, "/cam");
  m.height = 480;
  m.width = 640;
  m.distortion_model = "plumb_bob";
  m.d = {0.1, -0.2, 0.001, 0.002, 0.3};
  m.k = {525, 0, 319.5, 0, 525, 239.5, 0, 0, 1};
  m.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  m.p = {525, 0, 319.5, 0, 0, 525, 239.5, 0, 0, 0, 1, 0};
  m.binning_x = 2;
  m.binning_y = 3;
  m.roi = {4, 5, 6, 7, true};
  const std::vector<std::uint8_t> bytes = msg::encode(m);
  // After the 4-byte encapsulation, offsets count from 0: stamp 0-7, "/cam" 8-16, height and width
  // 20-27, "plumb_bob" 28-41, d's count 44-47, its doubles from 48 (8-aligned), then k, r, p: 35
  // doubles to 328, binning 328-335, roi 336-351, do_rectify 352.
  EXPECT_EQ(bytes.size(), 4u + 48 + 35 * 8 + 6 * 4 + 1);
  double first_d = 0.0;
  std::memcpy(&first_d, bytes.data() + 4 + 48, 8);
  EXPECT_EQ(first_d, 0.1);
  const msg::CameraInfo back = msg::decode_camera_info(bytes.data(), bytes.size());
  EXPECT_EQ(back.header.stamp.sec, -3);
  EXPECT_EQ(back.header.stamp.nanosec, 999999999u);
  EXPECT_EQ(back.header.frame_id, "/cam");
  EXPECT_EQ(back.distortion_model, "plumb_bob");
  EXPECT_EQ(back.d, m.d);
  EXPECT_EQ(back.k, m.k);
  EXPECT_EQ(back.r, m.r);
  EXPECT_EQ(back.p, m.p);
  EXPECT_EQ(back.binning_y, 3u);
  EXPECT_EQ(back.roi.width, 7u);
  EXPECT_TRUE(back.roi.do_rectify);
}

TEST(Cdr, TfMessageRoundTrips) {
  msg::TFMessage m;
  for (int i = 0; i < 3; ++i) {
    msg::TransformStamped t;
    t.header = header_of(100 + i, 5u * i, "/world");
    t.child_frame_id = "/kinect" + std::to_string(i);
    t.transform = {{0.5 * i, -1.25, 3.0}, {0.0, 0.6, 0.0, 0.8}};
    m.transforms.push_back(t);
  }
  const std::vector<std::uint8_t> bytes = msg::encode(m);
  const msg::TFMessage back = msg::decode_tf_message(bytes.data(), bytes.size());
  ASSERT_EQ(back.transforms.size(), 3u);
  EXPECT_EQ(back.transforms[2].header.stamp.sec, 102);
  EXPECT_EQ(back.transforms[2].header.stamp.nanosec, 10u);
  EXPECT_EQ(back.transforms[2].child_frame_id, "/kinect2");
  EXPECT_EQ(back.transforms[1].transform.translation.x, 0.5);
  EXPECT_EQ(back.transforms[1].transform.rotation.y, 0.6);
  EXPECT_EQ(back.transforms[1].transform.rotation.w, 0.8);
}

TEST(Cdr, AShortMessageNamesTheFieldItEndsIn) {
  msg::Image m;
  m.header = header_of(1, 2, "f");
  m.encoding = "rgb8";
  m.data.assign(100, 1);
  const std::vector<std::uint8_t> bytes = msg::encode(m);
  const std::string e = error_of([&] { (void)msg::decode_image(bytes.data(), bytes.size() - 10); });
  EXPECT_NE(e.find("ends inside 'data'"), std::string::npos) << e;
  const std::string h = error_of([&] { (void)msg::decode_image(bytes.data(), 10); });
  EXPECT_NE(h.find("ends inside 'header.stamp.nanosec'"), std::string::npos) << h;
  const std::vector<std::uint8_t> big_endian = {0, 0, 0, 0, 1, 2, 3, 4};
  EXPECT_NE(error_of([&] {
              (void)msg::decode_header(big_endian.data(), big_endian.size());
            }).find("not little-endian"),
            std::string::npos);
}

TEST(Cdr, DefinitionsNameEveryTypeTheyUse) {
  const std::string d = msg::definition(msg::kTfMessageType);
  EXPECT_EQ(d.rfind("geometry_msgs/TransformStamped[] transforms\n", 0), 0u);
  EXPECT_NE(d.find(std::string(80, '=') + "\nMSG: geometry_msgs/Quaternion\n"), std::string::npos);
  EXPECT_NE(msg::definition(msg::kCameraInfoType).find("MSG: sensor_msgs/RegionOfInterest\n"),
            std::string::npos);
  EXPECT_NE(error_of([] { (void)msg::definition("std_msgs/msg/String"); }).find("std_msgs/msg/String"),
            std::string::npos);
}

struct Written {
  std::string topic;
  std::uint64_t time;
  std::vector<std::uint8_t> data;
};

// Two channels, 40 messages of 1-3 kB: several chunks at a 16 kB chunk size.
std::vector<Written> write_sample_mcap(const fs::path& file, Compression compression) {
  McapWriter w(file, {compression, 16 << 10, "ros2"});
  const std::uint16_t image = w.add_schema(msg::kImageType, "ros2msg", msg::definition(msg::kImageType));
  const std::uint16_t tf = w.add_schema(msg::kTfMessageType, "ros2msg", msg::definition(msg::kTfMessageType));
  const std::uint16_t a = w.add_channel(image, "/camera/rgb/image_color", "cdr");
  const std::uint16_t b = w.add_channel(tf, "/tf", "cdr");
  std::vector<Written> out;
  for (int i = 0; i < 40; ++i) {
    std::vector<std::uint8_t> data(1000 + 50 * i);
    for (std::size_t k = 0; k < data.size(); ++k) data[k] = static_cast<std::uint8_t>(k * 7 + i);
    const bool on_a = i % 3 != 0;
    out.push_back({on_a ? "/camera/rgb/image_color" : "/tf", 1000000000ull + 33000000ull * i, data});
    w.write(on_a ? a : b, out.back().time, data);
  }
  w.close();
  return out;
}

void expect_reads_back(Compression compression) {
  SCOPED_TRACE(std::string("compression '") + compression_name(compression) + "'");
  TempDir dir("mcap");
  const fs::path file = dir.path() / "x.mcap";
  const std::vector<Written> written = write_sample_mcap(file, compression);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), {}), 1);  // no temporary beside it
  const McapReader r(file);
  EXPECT_EQ(r.profile(), "ros2");
  EXPECT_EQ(r.topics().at("/camera/rgb/image_color"), msg::kImageType);
  EXPECT_EQ(r.topics().at("/tf"), msg::kTfMessageType);
  std::size_t seen = 0;
  for (const std::string topic : {"/camera/rgb/image_color", "/tf"}) {
    std::vector<Written> expected;
    for (const Written& w : written)
      if (w.topic == topic) expected.push_back(w);
    const std::vector<MessageRef> refs = r.messages(topic);
    ASSERT_EQ(refs.size(), expected.size()) << topic;
    for (std::size_t k = 0; k < refs.size(); ++k) {
      EXPECT_EQ(static_cast<std::uint64_t>(refs[k].log_time_ns), expected[k].time);
      EXPECT_EQ(r.read(refs[k]), expected[k].data) << topic << " " << k;
      EXPECT_NE(refs[k].a, 0u) << "messages are in chunks";
    }
    seen += refs.size();
  }
  EXPECT_EQ(seen, 40u);
}

TEST(Mcap, UncompressedChunksReadBackByteForByte) {
  expect_reads_back(Compression::none);
}
TEST(Mcap, ZstdChunksReadBackByteForByte) {
  expect_reads_back(Compression::zstd);
}
TEST(Mcap, Lz4ChunksReadBackByteForByte) {
  expect_reads_back(Compression::lz4);
}

TEST(Mcap, CompressedChunksAreSmallerAndEndInASummary) {
  TempDir dir("mcap");
  (void)write_sample_mcap(dir.path() / "none.mcap", Compression::none);
  (void)write_sample_mcap(dir.path() / "zstd.mcap", Compression::zstd);
  (void)write_sample_mcap(dir.path() / "lz4.mcap", Compression::lz4);
  const auto size = [&](const char* name) { return fs::file_size(dir.path() / name); };
  EXPECT_LT(size("zstd.mcap"), size("none.mcap") / 4);
  EXPECT_LT(size("lz4.mcap"), size("none.mcap") / 2);
  // The footer: summary start and summary offsets start, both inside the file, then the magic.
  const std::string bytes = TempDir::read(dir.path() / "zstd.mcap");
  ASSERT_GT(bytes.size(), 37u);
  const std::size_t footer = bytes.size() - 8 - 29;
  EXPECT_EQ(static_cast<std::uint8_t>(bytes[footer]), mcap::kFooter);
  std::uint64_t summary_start = 0, offsets_start = 0;
  std::memcpy(&summary_start, bytes.data() + footer + 9, 8);
  std::memcpy(&offsets_start, bytes.data() + footer + 17, 8);
  EXPECT_GT(summary_start, 8u);
  EXPECT_GT(offsets_start, summary_start);
  EXPECT_EQ(static_cast<std::uint8_t>(bytes[summary_start]), mcap::kSchema);
  EXPECT_EQ(static_cast<std::uint8_t>(bytes[offsets_start]), mcap::kSummaryOffset);
}

// A hand-made file: header, one chunk with the given compression name and records, data end,
// footer.
void write_raw_mcap(const fs::path& file, const std::string& compression,
                    const std::vector<std::uint8_t>& records, std::uint32_t crc) {
  using namespace mcap;
  std::vector<std::uint8_t> out(std::begin(kMagic), std::end(kMagic));
  const auto append = [&](const std::vector<std::uint8_t>& r) { out.insert(out.end(), r.begin(), r.end()); };
  append(record(kHeader, RecordBuilder().string("ros2").string("test")));
  append(record(kChunk, RecordBuilder()
                            .u64(0)
                            .u64(0)
                            .u64(records.size())
                            .u32(crc)
                            .string(compression)
                            .u64(records.size())
                            .raw(records.data(), records.size())));
  append(record(kDataEnd, RecordBuilder().u32(0)));
  append(record(kFooter, RecordBuilder().u64(0).u64(0).u32(0)));
  out.insert(out.end(), std::begin(kMagic), std::end(kMagic));
  std::ofstream(file, std::ios::binary)
      .write(reinterpret_cast<const char*>(out.data()), static_cast<std::streamsize>(out.size()));
}

std::vector<std::uint8_t> sample_records() {
  using namespace mcap;
  std::vector<std::uint8_t> r = record(
      kSchema, RecordBuilder().u16(1).string(msg::kImageType).string("ros2msg").bytes(bytes_of("uint8 x")));
  const auto channel = record(kChannel, RecordBuilder().u16(1).u16(1).string("/img").string("cdr").u32(0));
  r.insert(r.end(), channel.begin(), channel.end());
  return r;
}

TEST(Mcap, BrokenFilesAreOneLineErrorsNamingTheFile) {
  TempDir dir("mcap");
  const fs::path good = dir.path() / "good.mcap";
  (void)write_sample_mcap(good, Compression::zstd);
  const std::string bytes = TempDir::read(good);
  const auto expect_error = [](const fs::path& file, const std::string& part) {
    const std::string e = error_of([&] { McapReader r(file); });
    EXPECT_EQ(e.rfind(file.string() + ": ", 0), 0u) << e;
    EXPECT_NE(e.find(part), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_EQ(e.find(file.string(), 1), std::string::npos) << "the file named once: " << e;
  };
  for (const std::size_t keep : {bytes.size() - 1, bytes.size() / 2, std::size_t{20}, std::size_t{3}})
    expect_error(dir.write("cut" + std::to_string(keep) + ".mcap", bytes.substr(0, keep)),
                 keep < 8 ? "not an MCAP file" : "truncated MCAP file");
  const std::vector<std::uint8_t> records = sample_records();
  const std::uint32_t crc = mcap::crc32(records.data(), records.size());
  write_raw_mcap(dir.path() / "raw.mcap", "", records, crc);
  EXPECT_EQ(McapReader(dir.path() / "raw.mcap").topics().at("/img"), msg::kImageType);
  write_raw_mcap(dir.path() / "crc.mcap", "", records, crc ^ 1u);
  expect_error(dir.path() / "crc.mcap", "CRC mismatch");
  write_raw_mcap(dir.path() / "brotli.mcap", "brotli", records, crc);
  expect_error(dir.path() / "brotli.mcap", "unknown compression 'brotli'");
  write_raw_mcap(dir.path() / "lz4.mcap", "lz4", records, crc);  // not an LZ4 frame
  expect_error(dir.path() / "lz4.mcap", "lz4 data is corrupt");
  expect_error(dir.write("text.mcap", "hello, not an MCAP file at all"), "not an MCAP file");
}

TEST(Rosbag2Sqlite3, WhatIsWrittenReadsBackWithItsTopics) {
  TempDir dir("db3");
  const fs::path file = dir.path() / "x.db3";
  {
    Sqlite3Writer w(file);
    const std::int64_t a = w.add_topic({"/camera/depth/image", msg::kImageType});
    const std::int64_t b = w.add_topic({"/tf", msg::kTfMessageType});
    for (int i = 5; i >= 0; --i) w.write(i % 2 ? a : b, 1000 + i, std::vector<std::uint8_t>(10 + i, 1 + i));
    EXPECT_FALSE(fs::exists(file));  // written beside, renamed by close()
    w.close();
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), {}), 1);  // no temporary beside it
  const Sqlite3Reader r(file);
  EXPECT_EQ(r.topics().size(), 2u);
  EXPECT_EQ(r.topics().at("/camera/depth/image"), msg::kImageType);
  const std::vector<MessageRef> depth = r.messages("/camera/depth/image");
  ASSERT_EQ(depth.size(), 3u);
  EXPECT_EQ(depth[0].log_time_ns, 1001);  // by record time, not insertion order
  EXPECT_EQ(depth[2].log_time_ns, 1005);
  EXPECT_EQ(r.read(depth[2]), std::vector<std::uint8_t>(15, 6));
  EXPECT_TRUE(r.messages("/nothing").empty());
}

TEST(Rosbag2Sqlite3, TruncatedOrForeignFilesAreOneLineErrors) {
  TempDir dir("db3");
  const fs::path file = dir.path() / "x.db3";
  {
    Sqlite3Writer w(file);
    const std::int64_t a = w.add_topic({"/img", msg::kImageType});
    for (int i = 0; i < 50; ++i) w.write(a, i, std::vector<std::uint8_t>(4000, 3));
    w.close();
  }
  const std::string bytes = TempDir::read(file);
  const fs::path cut = dir.write("cut.db3", bytes.substr(0, bytes.size() / 2));
  const std::string e = error_of([&] { Sqlite3Reader r(cut); });
  EXPECT_EQ(e.rfind(cut.string() + ": truncated SQLite database", 0), 0u) << e;
  const fs::path text = dir.write("text.db3", std::string(200, 'x'));
  EXPECT_NE(error_of([&] { Sqlite3Reader r(text); }).find(text.string() + ": not a SQLite database"),
            std::string::npos);
  const fs::path header_only = dir.write("short.db3", bytes.substr(0, 50));
  EXPECT_NE(error_of([&] { Sqlite3Reader r(header_only); }).find("not a SQLite database"), std::string::npos);
}

}  // namespace
}  // namespace lrd::rosbag2
