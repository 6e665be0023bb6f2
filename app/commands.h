#pragma once
// Each subcommand of the `lrdslam` CLI lives in its own cmd_*.cc and registers itself here.
// A registered callback throws lrd::Error for bad input; main() prints it on one line and exits 1.
#include <CLI/CLI.hpp>

namespace lrd::app {

void register_synth_command(CLI::App& app);
void register_eval_command(CLI::App& app);
void register_run_command(CLI::App& app);
void register_segment_command(CLI::App& app);
void register_eval_map_command(CLI::App& app);
void register_vocab_command(CLI::App& app);
void register_report_command(CLI::App& app);
void register_sweep_command(CLI::App& app);
void register_ros2_play_command(CLI::App& app);
void register_map_command(CLI::App& app);

}  // namespace lrd::app
