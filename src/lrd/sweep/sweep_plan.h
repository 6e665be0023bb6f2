#pragma once
// A sweep: the paper's experiment as a grid of `lrdslam run` cells — inputs (TUM-layout folders,
// bags, synthetic presets) x modes x config variants x repeats. The plan is written to
// DIR/manifest.json before anything runs; running the same sweep again finds it and resumes.
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace lrd::sweep {

struct SweepSpec {
  std::vector<std::filesystem::path> sequences;  // TUM-layout folders and bags
  std::vector<std::string> presets;              // synthetic presets, rendered by each run
  std::vector<int> seeds{1};
  int frames = -1;                 // presets: a prefix (< 0: the preset's length)
  std::string realism = "clean";   // presets
  std::vector<std::string> modes;  // static, semantic, geometric, full
  int repeats = 1;
  bool deterministic = false;
  std::string segmenter;                                  // empty: each run's default
  std::map<std::string, std::filesystem::path> variants;  // --config-variant name=FILE (ordered by name)
  std::vector<std::string> sets;                          // --set key=value, applied to every variant
  std::vector<std::string> run_args;                      // passed to every `lrdslam run` as given
};

// One `lrdslam run` of the sweep.
struct SweepCell {
  int index = 0;
  std::string id;        // SEQUENCE__MODE__VARIANT__rREPEAT, the cell's folder name
  std::string sequence;  // label in the tables: the folder's or bag's name, or preset[@seed][.realism]
  std::string mode;
  std::string variant;  // "default" without --config-variant
  int repeat = 0;
  std::vector<std::string> args;  // `lrdslam run` arguments, without --out
};

struct SweepPlan {
  SweepSpec spec;
  std::vector<SweepCell> cells;
  std::map<std::string, std::string> configs;  // variant -> the YAML text its cells run with
};

// Checks the spec (unknown presets and modes, folders that are not sequences, bad --set) with
// one-line lrd::Error messages, and lays out the cells. Nothing is written.
[[nodiscard]] SweepPlan plan_sweep(const SweepSpec& spec);

// DIR/manifest.json and DIR/configs/VARIANT.yaml (each written beside and renamed into place).
// An existing manifest must describe the same cells: a different sweep in DIR is an error.
void write_manifest(const std::filesystem::path& dir, const SweepPlan& plan);
// The cells of DIR/manifest.json; throws lrd::Error naming the file.
[[nodiscard]] std::vector<SweepCell> read_manifest(const std::filesystem::path& dir);

[[nodiscard]] nlohmann::json cell_json(const SweepCell& cell);

// 64-bit FNV-1a of `bytes` as 16 hex digits: the config hash every result records.
[[nodiscard]] std::string content_hash(const std::string& bytes);

}  // namespace lrd::sweep
