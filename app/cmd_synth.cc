// lrdslam synth: render a synthetic dynamic RGB-D sequence in the TUM layout.
#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>

#include "app/bag_input.h"
#include "app/commands.h"
#include "app/realism_options.h"
#include "lrd/eval/motion_statistics.h"
#include "lrd/synth/motion_matching.h"
#include "lrd/synth/presets.h"
#include "lrd/synth/sequence_writer.h"
#include "lrd/synth/synthetic_sequence.h"
#include "lrd/synth/voc_exporter.h"
#include "lrd/util/error.h"

namespace lrd::app {

namespace {

void print_motion(const synth::SyntheticSequence& seq) {
  const auto m = eval::motion_statistics(seq.ground_truth());
  std::printf("camera motion (TUM's 1-s windows): %.2f s, %.3f m, mean %.3f m/s and %.2f deg/s\n", m.duration,
              m.length, m.mean_speed, m.mean_angular_speed);
  const synth::PresetSpec& spec = seq.spec();
  if (const auto tum = synth::motion_target(spec))
    std::printf("TUM's fr3/%s (dataset page): mean %.3f m/s and %.2f deg/s\n",
                synth::motion_model(spec).c_str(), tum->mean_speed, tum->mean_angular_speed);
}

}  // namespace

void register_synth_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "synth", "Render a synthetic dynamic RGB-D sequence (TUM layout + ground-truth masks)");
  auto opts = std::make_shared<synth::SynthOptions>();
  auto out = std::make_shared<std::string>();
  auto list = std::make_shared<bool>(false);
  std::string preset_help = "Preset:";
  for (const auto& s : synth::preset_specs())
    preset_help += "\n  " + s.name + " (" + std::to_string(s.default_frames) + " frames): " + s.description;
  cmd->add_option("--preset", opts->preset, preset_help)->capture_default_str();
  cmd->add_option("--out", *out, "Output folder")->required(false);
  auto bag = std::make_shared<std::string>();
  cmd->add_option("--bag", *bag,
                  "Also write the sequence as a TUM-style bag (the TUM bags' topics, types and frame ids, "
                  "camera_info, /tf /world -> /kinect ground truth): FILE.bag for ROS 1, FILE.mcap (MCAP, "
                  "zstd chunks) or FILE.db3 (sqlite3, with metadata.yaml beside it) for ROS 2");
  cmd->add_option("--seed", opts->seed, "Random seed (actors' looks and timing, camera tremor, sensor noise)")
      ->capture_default_str();
  cmd->add_option("--frames", opts->frames,
                  "Number of frames (default: the preset's length; a prefix of it)");
  cmd->add_flag(
      "--motion-blur", opts->motion_blur,
      "Average 5 sub-frames over a 1/60 s exposure (the clean profile; tum blurs over its own exposure)");
  auto realism = std::make_shared<RealismOptions>();
  realism->add_to(cmd, nullptr);
  cmd->add_option("--camera-speed", opts->camera_speed,
                  "Run the preset's camera path this many times faster (e.g. static_loop at 2.5: its loop "
                  "closes near frame 210, for short tests)")
      ->check(CLI::Range(0.1, 10.0));
  cmd->add_option(
         "--session", opts->session,
         "Map-file session: 1 is the preset's camera path; 2 and 3 see the same room and people from "
         "another standpoint, starting turned away from the view session 1 sees, in the same world frame")
      ->check(CLI::Range(1, synth::CameraMotion::kMaxSession))
      ->capture_default_str();
  auto blank = std::make_shared<std::string>();
  cmd->add_option(
      "--blank", *blank,
      "START:COUNT - frames START.. are black without depth (a covered lens) while the camera moves on: "
      "a relocalization test");
  cmd->add_flag("--list", *list, "List the presets and exit");
  auto motion_only = std::make_shared<bool>(false);
  cmd->add_flag("--motion-stats", *motion_only,
                "Print the camera motion's statistics as TUM states them (duration, length, mean speeds over "
                "1-s windows) without rendering, and exit");
  auto voc_dir = std::make_shared<std::string>();
  auto voc_images = std::make_shared<int>(2000);
  cmd->add_option(
      "--export-voc", *voc_dir,
      "Instead of one sequence, write segmentation training data in the Pascal VOC layout to this "
      "folder (frames of every preset; seeds from --seed, default 1000, disjoint from evaluation seeds)");
  cmd->add_option("--images", *voc_images, "With --export-voc: number of images")->capture_default_str();
  auto* seed_opt = cmd->get_option("--seed");
  cmd->callback([opts, out, list, voc_dir, voc_images, seed_opt, blank, bag, realism, motion_only] {
    opts->realism = realism->params();
    if (!blank->empty()) {
      int from = -1, count = -1;
      char rest = 0;
      if (std::sscanf(blank->c_str(), "%d:%d%c", &from, &count, &rest) != 2 || from < 0 || count <= 0)
        throw Error("synth: --blank expects START:COUNT with START >= 0 and COUNT > 0, got '" + *blank + "'");
      opts->blank_from = from;
      opts->blank_count = count;
    }
    if (!voc_dir->empty()) {
      synth::VocExportOptions v;
      v.images = *voc_images;
      if (seed_opt->count() > 0) v.first_seed = opts->seed;
      const bool tty = isatty(fileno(stderr));
      const auto s = synth::export_voc(*voc_dir, v, [tty](int done, int total) {
        if (tty && (done % 20 == 0 || done == total)) std::fprintf(stderr, "\r  %d/%d images", done, total);
      });
      if (tty) std::fprintf(stderr, "\n");
      std::printf("VOC export: %d train + %d val images in %.1f s -> %s (person pixels: %.1f %%)\n", s.train,
                  s.val, s.seconds, voc_dir->c_str(), 100 * s.person_pixel_fraction);
      return;
    }
    if (*list) {
      for (const auto& s : synth::preset_specs())
        std::printf("%-20s %5d frames  %s\n", s.name.c_str(), s.default_frames, s.description.c_str());
      return;
    }
    if (*motion_only) {
      print_motion(synth::SyntheticSequence(*opts));
      return;
    }
    if (out->empty()) throw Error("synth: --out DIR is required");
    const synth::SyntheticSequence seq(*opts);
    std::fprintf(stderr, "synth: %s, seed %llu, %d frames, realism %s -> %s\n", seq.spec().name.c_str(),
                 static_cast<unsigned long long>(opts->seed), seq.size(), opts->realism.profile.c_str(),
                 out->c_str());
    const bool tty = isatty(fileno(stderr));
    const auto summary = synth::write_sequence(seq, *out, [tty](int done, int total) {
      if (tty && (done % 10 == 0 || done == total)) std::fprintf(stderr, "\r  %d/%d frames", done, total);
    });
    if (tty) std::fprintf(stderr, "\n");
    std::printf(
        "%s: %d frames in %.1f s (%.1f frames/s); people/objects cover %.1f %% of the image on average "
        "(median %.1f %%, max %.1f %%), 20-50 %% in %.0f %% of frames\n",
        seq.spec().name.c_str(), summary.frames, summary.seconds, summary.frames / summary.seconds,
        100 * summary.mean_dynamic_fraction, 100 * summary.median_dynamic_fraction,
        100 * summary.max_dynamic_fraction, 100 * summary.frames_with_20_to_50_percent);
    print_motion(seq);
    if (!bag->empty()) {
      write_folder_as_bag(*out, *bag);
      std::printf("wrote %s\n", bag->c_str());
    }
  });
}

}  // namespace lrd::app
