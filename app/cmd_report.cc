// `lrdslam report RUN_DIR [--sequence SEQ] [--out FILE.html]`: one self-contained HTML page about a
// run (docs/report.md); `run --report` writes the same page into its output folder. Given a folder
// bench_dynamic wrote (results.json), the page shows the benchmark instead.
#include <cstdio>
#include <memory>

#include "app/commands.h"
#include "lrd/report/benchmark_data.h"
#include "lrd/report/html_page.h"
#include "lrd/report/run_data.h"
#include "lrd/util/error.h"

namespace lrd::app {
namespace {

struct ReportCli {
  std::string run_dir, sequence, out;
};

}  // namespace

void register_report_command(CLI::App& app) {
  auto cli = std::make_shared<ReportCli>();
  CLI::App* cmd = app.add_subcommand(
      "report",
      "Write one self-contained HTML page about a run: summary, trajectory against ground truth, "
      "error and tracking over time, time per stage, the maps; or about a benchmark: its tables and "
      "every mode's trajectories");
  cmd->add_option("run_dir", cli->run_dir,
                  "A folder `lrdslam run --out` wrote, or one bench_dynamic wrote (with results.json)")
      ->required();
  cmd->add_option("--sequence", cli->sequence,
                  "The sequence folder run (for its groundtruth.txt); default: the one summary.json names");
  cmd->add_option("--out", cli->out, "The page to write (default: RUN_DIR/report.html)");
  cmd->callback([cli] {
    report::RunSources sources{cli->run_dir, std::nullopt};
    if (!cli->sequence.empty()) sources.sequence = cli->sequence;
    const std::filesystem::path out = cli->out.empty() ? std::filesystem::path(cli->run_dir) / "report.html"
                                                       : std::filesystem::path(cli->out);
    const bool benchmark = report::is_benchmark_folder(cli->run_dir);
    if (benchmark && !cli->sequence.empty())
      throw Error("report: --sequence is for a run's folder; " + cli->run_dir +
                  " is a benchmark's (each run names its own sequence)");
    report::write_html_report(
        out, benchmark ? report::collect_benchmark_data(cli->run_dir) : report::collect_run_data(sources));
    std::printf("wrote %s\n", out.string().c_str());
  });
}

}  // namespace lrd::app
