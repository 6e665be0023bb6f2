#include "lrd/report/html_page.h"

#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"
#include "lrd/util/project_files.h"

namespace lrd::report {
namespace fs = std::filesystem;

namespace {

struct Asset {
  const char* file;     // relative to the project root
  const char* fetched;  // the script that fetches it, or nullptr when it is tracked
};

std::string read_asset(const Asset& asset) {
  const fs::path file = util::find_project_file(asset.file);
  if (!fs::exists(file))
    throw file_error(file, asset.fetched != nullptr
                               ? std::string("missing: the report inlines it; run ") + asset.fetched
                               : std::string("missing (the report's own script and style are in web/)"));
  std::string text = util::read_file_bytes(file, "report asset");
  // A script or style is inlined as it is: one that could close its element early is refused.
  if (text.find("</script") != std::string::npos || text.find("</style") != std::string::npos)
    throw file_error(file, "holds a closing </script> or </style> tag: it cannot be inlined");
  return text;
}

// Inside <script> only "</" can end the element early; JSON allows "<\/" for it.
std::string escape_json_for_script(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    out += text[i];
    if (text[i] == '<' && i + 1 < text.size() && text[i + 1] == '/') out += '\\';
  }
  return out;
}

std::string html_escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

}  // namespace

std::string base64(const std::string& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k)
      v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kAlphabet[(v >> (18 - 6 * k)) & 63u] : '=';
  }
  return out;
}

constexpr Asset kUplot{"data/web/uPlot.iife.min.js", "scripts/fetch-web-assets.sh"};
constexpr Asset kUplotCss{"data/web/uPlot.min.css", "scripts/fetch-web-assets.sh"};
constexpr Asset kThree{"data/web/three.min.js", "scripts/fetch-web-assets.sh"};
constexpr Asset kOrbitControls{"data/web/three.OrbitControls.js", "scripts/fetch-web-assets.sh"};
constexpr Asset kMapScript{"web/map3d.js", nullptr};
constexpr Asset kCommonScript{"web/common.js", nullptr};  // helpers both pages use
constexpr Asset kRunScript{"web/report.js", nullptr};
constexpr Asset kBenchmarkScript{"web/benchmark.js", nullptr};
constexpr Asset kStyle{"web/report.css", nullptr};

void check_report_assets() {
  for (const Asset& asset : {kUplot, kUplotCss, kThree, kOrbitControls, kMapScript, kCommonScript, kRunScript,
                             kBenchmarkScript, kStyle})
    (void)read_asset(asset);
}

void write_html_report(const fs::path& file, const nlohmann::json& data) {
  std::string page;
  page += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  page += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  // A run's page (run_data.h) or a benchmark's (benchmark_data.h): the data say which.
  const bool benchmark = data.value("kind", std::string()) == "benchmark";
  page += std::string("<title>lrd-slam ") + (benchmark ? "benchmark" : "report") + ": " +
          html_escape(data.value("run", std::string("run"))) + "</title>\n";
  page += "<style>\n" + read_asset(kUplotCss) + "\n</style>\n";
  page += "<style>\n" + read_asset(kStyle) + "\n</style>\n</head>\n<body>\n";
  page += "<noscript>This report draws its charts with JavaScript.</noscript>\n<main id=\"report\"></main>\n";
  page += "<script type=\"application/json\" id=\"report-data\">" + escape_json_for_script(data.dump()) +
          "</script>\n";
  page += "<script>\n" + read_asset(kUplot) + "\n</script>\n";
  // three.js only where the page draws a 3-D map: it is most of a small page's size.
  if (data.contains("map3d")) {
    page += "<script>\n" + read_asset(kThree) + "\n</script>\n";
    page += "<script>\n" + read_asset(kOrbitControls) + "\n</script>\n";
  }
  page += "<script>\n" + read_asset(kCommonScript) + "\n</script>\n";
  if (data.contains("map3d")) page += "<script>\n" + read_asset(kMapScript) + "\n</script>\n";
  page += "<script>\n" + read_asset(benchmark ? kBenchmarkScript : kRunScript) +
          "\n</script>\n</body>\n</html>\n";
  util::write_file_bytes(file, page);
}

}  // namespace lrd::report
