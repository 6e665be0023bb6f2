"""A small benchmark folder as bench_dynamic writes it (results.json, runs/PRESET/MODE/) made with the
CLI: the report tests read it back. The results' fields are bench_dynamic's (bench/bench_dynamic.cc)."""
import json

from cli import lrdslam, synth_input

PRESETS = {"walking_xyz": 60, "static_xyz": 40}
MODES = ["static", "geometric"]


def stats(s):
    return {"rmse": s["rmse"], "mean": s["mean"], "median": s["median"], "std": 0.0}  # summary.json has no std


def make_benchmark_folder(d):
    """Runs every mode on short synthetic presets into d/bench; returns the folder."""
    bench = d / "bench"
    runs = []
    for preset, frames in PRESETS.items():
        seq = d / "sequences" / preset
        synth_input("--preset", preset, "--frames", frames, "--out", seq)
        for mode in MODES:
            out = bench / "runs" / preset / mode
            lrdslam("run", "--sequence", seq, "--mode", mode, "--deterministic", "--quiet", "--out", out)
            s = json.loads((out / "summary.json").read_text())
            total = s["per_frame"]["total"]
            y = 5.0  # a yardstick in ms: the page only divides by it
            runs.append({"preset": preset, "mode": mode, "run_dir": f"runs/{preset}/{mode}", "frames": s["frames"],
                         "lost": s["lost"], "keyframes": s["keyframes"], "y_ms": y,
                         "time_ms": {"mean": total["mean_ms"], "median": total["median_ms"]},
                         "time_y": {"mean": total["mean_ms"] / y, "median": total["median_ms"] / y},
                         "ate_m": stats(s["ate"]), "rpe_trans_m_per_s": {"rmse": s["rpe"]["trans_rmse"], "mean": 0, "median": 0, "std": 0},
                         "rpe_rot_deg_per_s": {"rmse": s["rpe"]["rot_rmse"], "mean": 0, "median": 0, "std": 0}})
    base = {r["preset"]: r for r in runs if r["mode"] == "static"}
    for r in runs:
        if r["mode"] != "static":
            b = base[r["preset"]]["ate_m"]["rmse"]
            r["eta_percent"] = {"ate_rmse": 100 * (b - r["ate_m"]["rmse"]) / b, "rpe_trans_rmse": 0, "rpe_rot_rmse": 0}
    (bench / "results.json").write_text(json.dumps(
        {"segmenter": "none", "seed": 1, "frames": -1, "presets": list(PRESETS), "modes": MODES, "runs": runs}, indent=2))
    return bench
