#include "lrd/rosbag2/messages.h"

#include "lrd/rosbag2/cdr.h"
#include "lrd/util/error.h"

namespace lrd::rosbag2::msg {

namespace {

void put(CdrWriter& w, const Header& h) {
  w.i32(h.stamp.sec);
  w.u32(h.stamp.nanosec);
  w.string(h.frame_id);
}

Header get_header(CdrReader& r) {
  Header h;
  h.stamp.sec = r.i32("header.stamp.sec");
  h.stamp.nanosec = r.u32("header.stamp.nanosec");
  h.frame_id = r.string("header.frame_id");
  return h;
}

void put(CdrWriter& w, const TransformStamped& t) {
  put(w, t.header);
  w.string(t.child_frame_id);
  const Vector3& v = t.transform.translation;
  const Quaternion& q = t.transform.rotation;
  for (const double x : {v.x, v.y, v.z, q.x, q.y, q.z, q.w}) w.f64(x);
}

TransformStamped get_transform(CdrReader& r) {
  TransformStamped t;
  t.header = get_header(r);
  t.child_frame_id = r.string("child_frame_id");
  Vector3& v = t.transform.translation;
  Quaternion& q = t.transform.rotation;
  for (double* x : {&v.x, &v.y, &v.z}) *x = r.f64("transform.translation");
  for (double* x : {&q.x, &q.y, &q.z, &q.w}) *x = r.f64("transform.rotation");
  return t;
}

}  // namespace

std::vector<std::uint8_t> encode(const Image& m) {
  CdrWriter w;
  put(w, m.header);
  w.u32(m.height);
  w.u32(m.width);
  w.string(m.encoding);
  w.u8(m.is_bigendian);
  w.u32(m.step);
  w.byte_sequence(m.data.data(), m.data.size());
  return w.take();
}

Image decode_image(const std::uint8_t* data, std::size_t size) {
  CdrReader r(data, size);
  Image m;
  m.header = get_header(r);
  m.height = r.u32("height");
  m.width = r.u32("width");
  m.encoding = r.string("encoding");
  m.is_bigendian = r.u8("is_bigendian");
  m.step = r.u32("step");
  const CdrReader::Bytes pixels = r.byte_sequence("data");
  m.data.assign(pixels.data, pixels.data + pixels.size);
  return m;
}

std::vector<std::uint8_t> encode(const CameraInfo& m) {
  CdrWriter w;
  put(w, m.header);
  w.u32(m.height);
  w.u32(m.width);
  w.string(m.distortion_model);
  w.sequence_length(m.d.size());
  w.f64_array(m.d.data(), m.d.size());
  w.f64_array(m.k.data(), m.k.size());
  w.f64_array(m.r.data(), m.r.size());
  w.f64_array(m.p.data(), m.p.size());
  w.u32(m.binning_x);
  w.u32(m.binning_y);
  for (const std::uint32_t x : {m.roi.x_offset, m.roi.y_offset, m.roi.height, m.roi.width}) w.u32(x);
  w.boolean(m.roi.do_rectify);
  return w.take();
}

CameraInfo decode_camera_info(const std::uint8_t* data, std::size_t size) {
  CdrReader r(data, size);
  CameraInfo m;
  m.header = get_header(r);
  m.height = r.u32("height");
  m.width = r.u32("width");
  m.distortion_model = r.string("distortion_model");
  m.d.resize(r.sequence_length("d", 8));
  r.f64_array("d", m.d.data(), m.d.size());
  r.f64_array("k", m.k.data(), m.k.size());
  r.f64_array("r", m.r.data(), m.r.size());
  r.f64_array("p", m.p.data(), m.p.size());
  m.binning_x = r.u32("binning_x");
  m.binning_y = r.u32("binning_y");
  m.roi.x_offset = r.u32("roi.x_offset");
  m.roi.y_offset = r.u32("roi.y_offset");
  m.roi.height = r.u32("roi.height");
  m.roi.width = r.u32("roi.width");
  m.roi.do_rectify = r.boolean("roi.do_rectify");
  return m;
}

std::vector<std::uint8_t> encode(const TFMessage& m) {
  CdrWriter w;
  w.sequence_length(m.transforms.size());
  for (const TransformStamped& t : m.transforms) put(w, t);
  return w.take();
}

TFMessage decode_tf_message(const std::uint8_t* data, std::size_t size) {
  CdrReader r(data, size);
  TFMessage m;
  // A TransformStamped is at least 4 + 4 + 8 (two empty strings) + 56 bytes.
  const std::size_t n = r.sequence_length("transforms", 72);
  for (std::size_t i = 0; i < n; ++i) m.transforms.push_back(get_transform(r));
  return m;
}

Header decode_header(const std::uint8_t* data, std::size_t size) {
  CdrReader r(data, size);
  return get_header(r);
}

}  // namespace lrd::rosbag2::msg
