"""Bad-input cases: ORB-SLAM2 settings and lrd-slam config files."""
import re

from bad_inputs.registry import case, garbage, make_dir, replace

# ---------------------------------------------------------------------------------------------
# 3. ORB-SLAM2 settings (--settings FILE, or the sequence's own settings.yaml)


def settings_text(ctx, key, value):
    text = (ctx.base / "settings.yaml").read_text()
    if value is None:
        new = re.sub(rf"^{re.escape(key)}:.*\n", "", text, flags=re.M)
    else:
        new = re.sub(rf"^{re.escape(key)}:.*$", f"{key}: {value}", text, flags=re.M)
    assert new != text, key
    return new


def settings_case(key, value, bug=None, in_sequence=False):
    def prepare(ctx):
        text = settings_text(ctx, key, value)
        if in_sequence:
            ctx.copy_seq()
            replace(ctx.seq / "settings.yaml", text)
            return [], "settings.yaml"
        f = replace(ctx.tmp / "bad_settings.yaml", text)
        return ["--settings", f], f.name

    shown = "missing" if value is None else value.strip('"')
    case(f"settings{'-in-sequence' if in_sequence else ''}-{key}={shown}", prepare, bug)


for key, value in [
    ("Camera.fx", ".nan"), ("Camera.fx", "-535.4"), ("Camera.fy", ".inf"),
    ("Camera.width", "0"), ("Camera.height", "1e12"),
    ("Camera.fps", "0"), ("DepthMapFactor", "-5000"),
    ("ORBextractor.nFeatures", "0"), ("ORBextractor.nLevels", "0"),
    ("Camera.k1", ".nan"), ("Camera.fx", '"fast"'), ("Camera.fx", None),
]:
    settings_case(key, value)
settings_case("DepthMapFactor", "0", in_sequence=True)

# Finite but absurd values (config/plausibility.h bounds every field, whichever file it comes from).
settings_case("Camera.fx", "1e300")
settings_case("Camera.cx", "-1e300")
settings_case("DepthMapFactor", "1e-300")
settings_case("ORBextractor.nLevels", "1000")
settings_case("ORBextractor.iniThFAST", "100000")
settings_case("ORBextractor.minThFAST", "1000")
settings_case("Camera.width", "100000")


def settings_file(id_, make, bug=None):
    def prepare(ctx):
        f = ctx.tmp / "bad_settings.yaml"
        make(ctx, f)
        return ["--settings", f], f.name

    case(id_, prepare, bug)


settings_file("settings-empty-file", lambda c, f: replace(f, b""))
settings_file("settings-binary-garbage", lambda c, f: replace(f, garbage(4000, seed=11)))
settings_file("settings-yaml-syntax-error", lambda c, f: replace(f, "%YAML:1.0\nCamera.fx: [535.4\nCamera.fy: 539.2\n"))
settings_file("settings-truncated-mid-line", lambda c, f: replace(f, (c.base / "settings.yaml").read_bytes()[:120]))
settings_file("settings-is-a-folder", lambda c, f: make_dir(f))

# ---------------------------------------------------------------------------------------------
# 4. lrd-slam config (--config FILE; the loader reports FILE:LINE)


def config_case(id_, text, bug=None):
    def prepare(ctx):
        f = replace(ctx.tmp / "bad_config.yaml", text)
        return ["--config", f], f.name

    case(f"config-{id_}", prepare, bug)


for id_, text in {
    "yaml-syntax-error": "tracking:\n  init_min_features: [500\n",
    "unknown-section": "trackng:\n  init_min_features: 500\n",
    "unknown-key": "tracking:\n  init_min_feature: 500\n",
    "duplicate-key": "tracking:\n  init_min_features: 500\n  init_min_features: 600\n",
    "wrong-type": "tracking:\n  init_min_features: lots\n",
    "int-overflow": "tracking:\n  init_min_features: 99999999999999999999\n",
    "top-level-list": "- camera\n- features\n",
    "camera.fx=.nan": "camera:\n  preset: tum3\n  fx: .nan\n",
    "camera.depth_map_factor=0": "camera:\n  preset: tum3\n  depth_map_factor: 0\n",
    "camera.preset=tum9": "camera:\n  preset: tum9\n",
    "features.n_levels=1000": "features:\n  n_levels: 1000\n",
    "features.min_th_fast-above-ini_th_fast": "features:\n  ini_th_fast: 10\n  min_th_fast: 20\n",
    "tracking.init_min_features=0": "tracking:\n  init_min_features: 0\n",
    "tracking.reference_ratio=1e300": "tracking:\n  reference_ratio: 1e300\n",
    "mapping.max_queued=0": "mapping:\n  max_queued: 0\n",
    "dynamic.geometry.max_parallax_deg=.nan": "dynamic:\n  geometry:\n    max_parallax_deg: .nan\n",
    "segmentation.stride=0": "segmentation:\n  stride: 0\n",
    "dense.voxel_size=.nan": "dense:\n  voxel_size: .nan\n",
}.items():
    config_case(id_, text)

# Values once unchecked (they ran to the end and exited 0): now range-checked with file:line.
for key, section, value in [
    ("cx", "camera:\n  preset: tum3\n  cx: {}\n", ".nan"),
    ("depth_map_factor", "camera:\n  preset: tum3\n  depth_map_factor: {}\n", ".inf"),
    ("scale_factor", "features:\n  scale_factor: {}\n", "1e30"),
    ("local_map_radius", "tracking:\n  local_map_radius: {}\n", ".nan"),
    ("max_frames_between_keyframes", "tracking:\n  max_frames_between_keyframes: {}\n", "-5"),
    ("fuse_neighbours", "mapping:\n  fuse_neighbours: {}\n", "-1"),
    ("ba_max_odometry_change_m", "mapping:\n  ba_max_odometry_change_m: {}\n", ".nan"),
    ("max_camera_speed", "tracking:\n  max_camera_speed: {}\n", ".nan"),
]:
    full = section.split(":")[0] + "." + key
    config_case(f"{full}={value}", section.format(value))
config_case("camera.width=2147483647", "camera:\n  preset: tum3\n  width: 2147483647\n")


def config_names_missing_settings(ctx):
    # the error names the settings file the config points at
    f = replace(ctx.tmp / "bad_config.yaml", "camera:\n  settings: no_such_settings.yaml\n")
    return ["--config", f], "no_such_settings.yaml"


case("config-camera.settings-missing", config_names_missing_settings)


def config_file(id_, make, bug=None):
    def prepare(ctx):
        f = ctx.tmp / "bad_config.yaml"
        make(ctx, f)
        return ["--config", f], f.name

    case(f"config-{id_}", prepare, bug)


config_file("binary-garbage", lambda c, f: replace(f, garbage(3000, seed=5)))
config_file("is-a-folder", lambda c, f: make_dir(f))
config_file("is-orbslam-settings", lambda c, f: replace(f, (c.base / "settings.yaml").read_bytes()))

