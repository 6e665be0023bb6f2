// `lrdslam eval`: ATE and RPE of an estimated trajectory against ground truth, defined exactly as
// TUM's evaluate_ate.py / evaluate_rpe.py (docs/evaluation.md), and the paper's improvement rate.
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/commands.h"
#include "lrd/eval/ate.h"
#include "lrd/eval/improvement.h"
#include "lrd/eval/plot.h"
#include "lrd/eval/rpe.h"
#include "lrd/io/trajectory.h"
#include "lrd/util/binary_io.h"
#include "lrd/util/error.h"

namespace lrd::app {
namespace {

struct EvalOptions {
  std::vector<std::string> files;
  bool compare = false;
  std::string json_file;
  std::string plot_dir;
  double max_dt = 0.02;
  double delta = 1.0;
  std::vector<std::string> align_with;  // GT_REF EST_REF: their best fit aligns EST (no fit of its own)
};

struct Evaluation {
  eval::AteResult ate;
  eval::RpeResult rpe;
};

// --align-with GT_REF EST_REF: the rigid alignment fitted to another trajectory in the same map
// (the session that made a map file), applied as is.
Eigen::Isometry3d reference_alignment(const EvalOptions& opt) {
  const std::string& gt_file = opt.align_with[0];
  const std::string& est_file = opt.align_with[1];
  try {
    return eval::compute_ate(io::read_trajectory_tum(gt_file), io::read_trajectory_tum(est_file), opt.max_dt)
        .alignment;
  } catch (const Error& e) {
    throw Error(fmt::format("--align-with: {} vs ground truth {}: {}", est_file, gt_file, e.what()));
  }
}

Evaluation evaluate(const io::Trajectory& gt, const io::Trajectory& est, const std::string& gt_file,
                    const std::string& est_file, const EvalOptions& opt) {
  // The evaluators know no file names; say which files the problem is about.
  try {
    if (!opt.align_with.empty()) {
      Evaluation e{eval::compute_ate(gt, est, reference_alignment(opt), opt.max_dt),
                   eval::compute_rpe(gt, est, opt.delta)};
      return e;
    }
    Evaluation e{eval::compute_ate(gt, est, opt.max_dt), eval::compute_rpe(gt, est, opt.delta)};
    return e;
  } catch (const Error& e) {
    throw Error(fmt::format("{} vs ground truth {}: {}", est_file, gt_file, e.what()));
  }
}

nlohmann::json stats_json(const eval::ErrorStats& s, bool with_count = true) {
  // nlohmann::json writes NaN (an undefined improvement rate) as null.
  nlohmann::json j = {{"rmse", s.rmse},   {"mean", s.mean}, {"median", s.median},
                      {"std", s.std_dev}, {"min", s.min},   {"max", s.max}};
  if (with_count) j["pairs"] = s.count;
  return j;
}

nlohmann::json evaluation_json(const Evaluation& e) {
  return {{"ate", stats_json(e.ate.stats)},
          {"rpe_trans", stats_json(e.rpe.trans)},
          {"rpe_rot", stats_json(e.rpe.rot)}};
}

void write_json(const std::string& file, const nlohmann::json& j) {
  if (file == "-") {
    std::fputs((j.dump(2) + "\n").c_str(), stdout);
    return;
  }
  util::write_file_bytes(file, j.dump(2) + '\n');
}

std::string rpe_unit(double delta, const char* unit) {
  if (delta == 1.0) return fmt::format("{}/s", unit);
  return fmt::format("{} per {:g} s", unit, delta);
}

struct Row {
  std::string name;
  eval::ErrorStats stats;
};

std::vector<Row> rows(const Evaluation& e, double delta) {
  return {{"ATE [m]", e.ate.stats},
          {fmt::format("RPE trans [{}]", rpe_unit(delta, "m")), e.rpe.trans},
          {fmt::format("RPE rot [{}]", rpe_unit(delta, "deg")), e.rpe.rot}};
}

void print_table(const Evaluation& e, const EvalOptions& opt) {
  fmt::print("{:<22}{:>12}{:>12}{:>12}{:>12}{:>12}{:>12}{:>8}\n", "", "rmse", "mean", "median", "std", "min",
             "max", "pairs");
  for (const Row& r : rows(e, opt.delta)) {
    const eval::ErrorStats& s = r.stats;
    fmt::print("{:<22}{:>12.6f}{:>12.6f}{:>12.6f}{:>12.6f}{:>12.6f}{:>12.6f}{:>8}\n", r.name, s.rmse, s.mean,
               s.median, s.std_dev, s.min, s.max, s.count);
  }
  if (opt.align_with.empty())
    fmt::print("ATE: {} pairs associated within {:g} s, rigidly aligned (no scale).\n", e.ate.stats.count,
               opt.max_dt);
  else
    fmt::print("ATE: {} pairs associated within {:g} s, aligned as {} onto {} (no fit of its own).\n",
               e.ate.stats.count, opt.max_dt, opt.align_with[1], opt.align_with[0]);
  fmt::print("RPE: all {} pairs {:g} s apart (no random subsampling).\n", e.rpe.trans.count, opt.delta);
}

std::string percent(double eta) {
  return std::isnan(eta) ? std::string("n/a") : fmt::format("{:+.2f}", eta);
}

void print_compare_table(const Evaluation& base, const Evaluation& ours, const EvalOptions& opt) {
  const std::vector<Row> b = rows(base, opt.delta), o = rows(ours, opt.delta);
  fmt::print("{:<22}{:>14}{:>14}{:>12}\n", "", "baseline", "ours", "eta [%]");
  for (std::size_t k = 0; k < b.size(); ++k) {
    const eval::ErrorStats& bs = b[k].stats;
    const eval::ErrorStats& os = o[k].stats;
    const std::pair<const char*, std::pair<double, double>> stats[] = {
        {"rmse", {bs.rmse, os.rmse}},      {"mean", {bs.mean, os.mean}}, {"median", {bs.median, os.median}},
        {"std", {bs.std_dev, os.std_dev}}, {"min", {bs.min, os.min}},    {"max", {bs.max, os.max}}};
    fmt::print("{}\n", b[k].name);
    for (const auto& [name, v] : stats) {
      fmt::print("  {:<20}{:>14.6f}{:>14.6f}{:>12}\n", name, v.first, v.second,
                 percent(eval::improvement_percent(v.first, v.second)));
    }
    fmt::print("  {:<20}{:>14}{:>14}\n", "pairs", bs.count, os.count);
  }
  fmt::print("eta = (baseline - ours) / baseline * 100 %; positive means ours is better.\n");
  fmt::print("RPE uses all pairs {:g} s apart (no random subsampling).\n", opt.delta);
}

void run_eval(const EvalOptions& opt) {
  if (opt.files.size() != 2) throw Error("eval: expected 2 files, GT EST (or use --compare BASE OURS GT)");
  const std::string& gt_file = opt.files[0];
  const std::string& est_file = opt.files[1];
  const io::Trajectory gt = io::read_trajectory_tum(gt_file);
  const io::Trajectory est = io::read_trajectory_tum(est_file);
  const Evaluation e = evaluate(gt, est, gt_file, est_file, opt);
  if (opt.json_file != "-") {
    fmt::print("ground truth: {}\nestimate:     {}\n\n", gt_file, est_file);
    print_table(e, opt);
  }
  if (!opt.json_file.empty()) write_json(opt.json_file, evaluation_json(e));
  if (!opt.plot_dir.empty()) eval::write_ate_plots(opt.plot_dir, gt, est, e.ate);
}

void run_compare(const EvalOptions& opt) {
  if (opt.files.size() != 3) throw Error("eval --compare: expected 3 files, BASE OURS GT");
  const std::string& base_file = opt.files[0];
  const std::string& ours_file = opt.files[1];
  const std::string& gt_file = opt.files[2];
  const io::Trajectory gt = io::read_trajectory_tum(gt_file);
  const io::Trajectory base_est = io::read_trajectory_tum(base_file);
  const io::Trajectory ours_est = io::read_trajectory_tum(ours_file);
  const Evaluation base = evaluate(gt, base_est, gt_file, base_file, opt);
  const Evaluation ours = evaluate(gt, ours_est, gt_file, ours_file, opt);
  if (opt.json_file != "-") {
    fmt::print("ground truth: {}\nbaseline:     {}\nours:         {}\n\n", gt_file, base_file, ours_file);
    print_compare_table(base, ours, opt);
  }
  if (!opt.json_file.empty()) {
    const nlohmann::json eta = {
        {"ate", stats_json(eval::improvement_percent(base.ate.stats, ours.ate.stats), false)},
        {"rpe_trans", stats_json(eval::improvement_percent(base.rpe.trans, ours.rpe.trans), false)},
        {"rpe_rot", stats_json(eval::improvement_percent(base.rpe.rot, ours.rpe.rot), false)}};
    write_json(
        opt.json_file,
        {{"baseline", evaluation_json(base)}, {"ours", evaluation_json(ours)}, {"improvement_percent", eta}});
  }
  if (!opt.plot_dir.empty()) {
    const std::filesystem::path dir(opt.plot_dir);
    eval::write_ate_plots(dir / "baseline", gt, base_est, base.ate);
    eval::write_ate_plots(dir / "ours", gt, ours_est, ours.ate);
  }
}

}  // namespace

void register_eval_command(CLI::App& app) {
  auto opt = std::make_shared<EvalOptions>();
  CLI::App* cmd = app.add_subcommand(
      "eval",
      "Evaluate a trajectory against ground truth: ATE and RPE exactly as TUM's evaluate_ate.py and "
      "evaluate_rpe.py --fixed_delta --delta_unit s.\n"
      "  lrdslam eval GT EST                   ATE (m), RPE trans (m/s) and rot (deg/s)\n"
      "  lrdslam eval --compare BASE OURS GT   both, with improvement eta = (base - ours) / base * 100 %\n"
      "Files are TUM format: 'timestamp tx ty tz qx qy qz qw' (camera-to-world).");
  cmd->footer(
      "RPE uses ALL pose pairs delta seconds apart: no random subsampling, unlike the TUM script, which "
      "samples 10,000 pairs at random when there are more.\n");
  cmd->add_option("files", opt->files, "GT EST, or with --compare: BASE OURS GT")
      ->required()
      ->type_name("FILE");
  cmd->add_flag("--compare", opt->compare, "Compare a baseline (BASE) with ours (OURS) against GT");
  cmd->add_option("--json", opt->json_file, "Also write the statistics as JSON to FILE ('-': stdout only)")
      ->type_name("FILE");
  cmd->add_option(
         "--plot", opt->plot_dir,
         "Write trajectory_top.png and ape_over_time.png to DIR (with --compare: DIR/baseline, DIR/ours)")
      ->type_name("DIR");
  cmd->add_option("--align-with", opt->align_with,
                  "GT_REF EST_REF: align EST with the rigid fit of EST_REF onto GT_REF instead of its own "
                  "(a session tracked in a loaded map, judged in the frame of the session that made it)")
      ->expected(2)
      ->type_name("FILE");
  cmd->add_option("--max-dt", opt->max_dt, "Largest timestamp difference for ATE association, seconds")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--delta", opt->delta,
                  "RPE pose distance, seconds (RPE over ALL pairs, no random subsampling)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->callback([opt] { opt->compare ? run_compare(*opt) : run_eval(*opt); });
}

}  // namespace lrd::app
