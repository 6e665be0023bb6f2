#pragma once
// The report as one self-contained HTML file: uPlot (data/web, fetched by
// scripts/fetch-web-assets.sh) and the page's own script and style (web/) inlined, the run's (or
// benchmark's) data as JSON and its images as data URIs; nothing is fetched when it opens.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace lrd::report {

// `data` as collect_run_data or collect_benchmark_data returns it. Throws lrd::Error naming an asset that is
// missing (and the script that fetches it) or the output file when it cannot be written.
void write_html_report(const std::filesystem::path& file, const nlohmann::json& data);

// The same error now, for a missing asset: `run --report` checks before tracking, not after.
void check_report_assets();

// RFC 4648 base64 (for data: URIs).
[[nodiscard]] std::string base64(const std::string& bytes);

}  // namespace lrd::report
