// lrdslam: the command-line front end. Subcommands live in cmd_*.cc.
#include <spdlog/spdlog.h>

#include <cstdio>
#include <exception>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include "app/commands.h"
#include "lrd/util/error.h"
#include "lrd/util/exception_message.h"
#include "lrd_git_commit.h"

int main(int argc, char** argv) {
  CLI::App app{"lrd-slam: RGB-D SLAM for dynamic scenes (LRD-SLAM)", "lrdslam"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("lrdslam ") + LRD_VERSION + " (" + LRD_GIT_COMMIT + ")");
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error, off")->capture_default_str();
  app.parse_complete_callback([&] { spdlog::set_level(spdlog::level::from_str(log_level)); });

  lrd::app::register_synth_command(app);
  lrd::app::register_eval_command(app);
  lrd::app::register_run_command(app);
  lrd::app::register_segment_command(app);
  lrd::app::register_eval_map_command(app);
  lrd::app::register_vocab_command(app);
  lrd::app::register_map_command(app);
  lrd::app::register_report_command(app);
  lrd::app::register_sweep_command(app);
  lrd::app::register_ros2_play_command(app);

  try {
    // OpenCV registers its image codecs on first use, GDAL's among them, and GDAL aborts the
    // process when it finds no memory for that: done here, before any thread or frame, a memory
    // limit (ulimit -v) is met later, where it is an error of one line.
    (void)cv::haveImageWriter(".png");
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // A usage error is one line, like every other error.
    std::fprintf(stderr, "error: %s (see --help)\n", e.what());
    return e.get_exit_code();
  } catch (const lrd::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  } catch (...) {
    // Anything else (std::bad_alloc under a memory limit, OpenCV's errors) as one line too.
    std::fprintf(stderr, "error: %s\n", lrd::util::exception_message(std::current_exception()).c_str());
    return 1;
  }
  return 0;
}
