#include "lrd/rosbag2/compression.h"

#include <fmt/format.h>
#include <lz4frame.h>
#include <zstd.h>

#include <memory>

#include "lrd/util/error.h"

namespace lrd::rosbag2 {

namespace {

std::vector<std::uint8_t> zstd_compress(const std::vector<std::uint8_t>& bytes) {
  std::vector<std::uint8_t> out(ZSTD_compressBound(bytes.size()));
  const std::size_t n = ZSTD_compress(out.data(), out.size(), bytes.data(), bytes.size(), 1);
  if (ZSTD_isError(n)) throw lrd::Error(std::string("zstd compression failed: ") + ZSTD_getErrorName(n));
  out.resize(n);
  return out;
}

std::vector<std::uint8_t> zstd_decompress(const std::uint8_t* data, std::size_t n, std::size_t size) {
  std::vector<std::uint8_t> out(size);
  const std::size_t got = ZSTD_decompress(out.data(), out.size(), data, n);
  if (ZSTD_isError(got)) throw lrd::Error(std::string("zstd data is corrupt: ") + ZSTD_getErrorName(got));
  if (got != size) throw lrd::Error(fmt::format("zstd data holds {} bytes, the chunk says {}", got, size));
  return out;
}

std::vector<std::uint8_t> lz4_compress(const std::vector<std::uint8_t>& bytes) {
  std::vector<std::uint8_t> out(LZ4F_compressFrameBound(bytes.size(), nullptr));
  const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), bytes.data(), bytes.size(), nullptr);
  if (LZ4F_isError(n)) throw lrd::Error(std::string("lz4 compression failed: ") + LZ4F_getErrorName(n));
  out.resize(n);
  return out;
}

std::vector<std::uint8_t> lz4_decompress(const std::uint8_t* data, std::size_t n, std::size_t size) {
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION)))
    throw lrd::Error("lz4: cannot create a decompression context");
  const std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> ctx(
      raw, &LZ4F_freeDecompressionContext);
  std::vector<std::uint8_t> out(size);
  std::size_t in_pos = 0, out_pos = 0, hint = 1;
  while (hint != 0) {
    std::size_t in_size = n - in_pos, out_size = out.size() - out_pos;
    hint = LZ4F_decompress(ctx.get(), out.data() + out_pos, &out_size, data + in_pos, &in_size, nullptr);
    if (LZ4F_isError(hint)) throw lrd::Error(std::string("lz4 data is corrupt: ") + LZ4F_getErrorName(hint));
    in_pos += in_size;
    out_pos += out_size;
    if (hint != 0 && in_size == 0 && out_size == 0) {
      const bool full = out_pos == out.size();
      throw lrd::Error(full ? fmt::format("lz4 data holds more than the chunk's {} bytes", size)
                            : fmt::format("lz4 data ends after {} of {} bytes", out_pos, size));
    }
  }
  if (out_pos != size)
    throw lrd::Error(fmt::format("lz4 data holds {} bytes, the chunk says {}", out_pos, size));
  return out;
}

}  // namespace

const char* compression_name(Compression c) {
  switch (c) {
    case Compression::zstd:
      return "zstd";
    case Compression::lz4:
      return "lz4";
    case Compression::none:
      break;
  }
  return "";
}

Compression compression_from_name(const std::string& name) {
  if (name.empty()) return Compression::none;
  if (name == "zstd") return Compression::zstd;
  if (name == "lz4") return Compression::lz4;
  throw lrd::Error("unknown compression '" + name + "' (none, zstd, lz4)");
}

std::vector<std::uint8_t> compress(Compression c, const std::vector<std::uint8_t>& bytes) {
  switch (c) {
    case Compression::zstd:
      return zstd_compress(bytes);
    case Compression::lz4:
      return lz4_compress(bytes);
    case Compression::none:
      break;
  }
  return bytes;
}

std::vector<std::uint8_t> decompress(Compression c, const std::uint8_t* data, std::size_t n,
                                     std::size_t size) {
  switch (c) {
    case Compression::zstd:
      return zstd_decompress(data, n, size);
    case Compression::lz4:
      return lz4_decompress(data, n, size);
    case Compression::none:
      break;
  }
  if (n != size) throw lrd::Error(fmt::format("an uncompressed chunk of {} bytes says {}", n, size));
  return {data, data + n};
}

}  // namespace lrd::rosbag2
