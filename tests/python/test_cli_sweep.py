"""`lrdslam sweep` with the local executor: the manifest, cells written whole, resuming, a failed
run recorded beside the others, the tables and results.json, and arguments checked before
anything runs."""
import json
import os
import re

import pytest

from cli import BIN, lrdslam, synth_input

GRID = ["--presets", "walking_xyz,static_xyz", "--frames", 40, "--modes", "static,geometric", "--repeats", 2,
        "--deterministic"]


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    d = tmp_path_factory.mktemp("sweep") / "grid"
    r = lrdslam("sweep", "--out", d, *GRID)
    return d, r.stdout


def test_a_local_sweep_fills_the_tables(swept):
    d, out = swept
    assert "8 cells, 8 to run" in out
    manifest = json.loads((d / "manifest.json").read_text())
    assert len(manifest["cells"]) == 8 and manifest["cells"][0]["index"] == 0
    results = json.loads((d / "results.json").read_text())
    assert (results["done"], results["failed"], results["missing"]) == (8, 0, 0)
    entries = {(e["sequence"], e["mode"]): e for e in results["entries"]}
    assert set(entries) == {(p, m) for p in ("walking_xyz", "static_xyz") for m in ("static", "geometric")}
    for e in entries.values():
        ate = e["ate_rmse_m"]
        assert len(ate["runs"]) == 2 and ate["spread"] == 0.0  # deterministic repeats agree exactly
        assert ate["median"] == ate["runs"][0] and e["time_per_frame_y"]["median"] > 0
        assert e["version"] and len(e["config_hash"]) == 16
    walking = entries[("walking_xyz", "geometric")]
    assert walking["ate_rmse_m"]["median"] < 0.03 < entries[("walking_xyz", "static")]["ate_rmse_m"]["median"]
    assert walking["eta_percent"]["ate_rmse_m"] > 50
    # Each cell is one `lrdslam run` into its own folder, with its provenance.
    cell = d / "cells" / "walking_xyz__geometric__default__r1"
    record = json.loads((cell / "result.json").read_text())
    assert record["summary"]["ate"]["rmse"] == walking["ate_rmse_m"]["runs"][1]
    assert record["cores"] >= 1 and record["host"] and record["job_id"].startswith("local:")
    assert (cell / "CameraTrajectory.txt").is_file()
    assert not any(p.name.startswith(".") for p in (d / "cells").iterdir())  # no partial cell left
    tables = (d / "tables.md").read_text()
    for title in ("Tables 4-5: ATE (m)", "Table 6: RPE translation", "Table 7: RPE rotation", "Table 10"):
        assert title in tables
    assert tables == out[out.index("# Sweep"):out.index("wrote ")]


def test_sequences_with_ground_truth_masks_get_the_flags_per_class(tmp_path):
    seq = tmp_path / "balloon"
    synth_input("--preset", "balloon", "--frames", 120, "--out", seq)
    d = tmp_path / "sweep"
    r = lrdslam("sweep", "--out", d, "--sequences", seq, "--modes", "static,geometric", "--deterministic")
    entries = {e["mode"]: e for e in json.loads((d / "results.json").read_text())["entries"]}
    run = json.loads((d / "cells" / "balloon__geometric__default__r0" / "result.json").read_text())["summary"]
    flags = entries["geometric"]
    assert flags["flag_precision"]["median"] == run["dynamic_flags"]["precision"]
    assert flags["balloon_recall"]["median"] == run["dynamic_flags"]["balloon_recall"] > 0.5
    assert flags["balloon_keypoints"]["median"] > 0 and flags["moved_object_keypoints"]["median"] == 0
    tables = (d / "tables.md").read_text()
    assert "Dynamic keypoint flags" in tables and "| balloon | geometric |" in tables
    assert "| balloon | static |" not in tables.split("Dynamic keypoint flags")[1]  # static flags nothing
    assert "moved objects" not in tables  # no class column the sequences do not show
    assert tables in r.stdout


def test_the_same_command_resumes_only_what_is_missing(swept, tmp_path):
    d, _ = swept
    import shutil
    shutil.rmtree(d / "cells" / "static_xyz__static__default__r0")
    status = lrdslam("sweep", "status", d).stdout
    assert "8 cells: 7 done, 0 failed, 1 missing" in status
    assert "missing: static_xyz__static__default__r0" in status
    stamp = (d / "cells" / "walking_xyz__static__default__r0" / "result.json").stat().st_mtime_ns
    again = lrdslam("sweep", "--out", d, *GRID).stdout
    assert "8 cells, 1 to run" in again
    assert (d / "cells" / "walking_xyz__static__default__r0" / "result.json").stat().st_mtime_ns == stamp
    assert json.loads((d / "results.json").read_text())["done"] == 8
    # Another grid in the same folder is refused.
    r = lrdslam("sweep", "--out", d, "--presets", "walking_xyz", "--modes", "full", check=False)
    assert r.returncode == 1 and "describes another sweep" in r.stderr


def test_a_failed_run_is_recorded_and_the_others_complete(tmp_path):
    good, bad = tmp_path / "good", tmp_path / "bad"
    synth_input("--preset", "static_xyz", "--frames", 40, "--out", good)
    synth_input("--preset", "static_xyz", "--frames", 40, "--out", bad)
    victim = sorted((bad / "rgb").iterdir())[5]
    victim.write_bytes(victim.read_bytes()[:200])  # a truncated PNG
    d = tmp_path / "sweep"
    r = lrdslam("sweep", "--out", d, "--sequences", f"{good},{bad}", "--modes", "static")
    assert "1 done, 1 failed" in r.stdout
    failed = json.loads((d / "cells" / "bad__static__default__r0.failed.json").read_text())
    assert victim.name in failed["error"] and "\n" not in failed["error"] and failed["exit_code"] == 1
    status = lrdslam("sweep", "status", d).stdout
    assert re.search(r"failed: bad__static__default__r0: .*" + re.escape(victim.name), status)
    results = json.loads((d / "results.json").read_text())
    assert results["failures"][0]["cell"] == "bad__static__default__r0"
    assert (d / "cells" / "good__static__default__r0" / "result.json").is_file()


@pytest.mark.parametrize("args, message", [
    (["--presets", "walking_nowhere", "--modes", "static"], "walking_nowhere"),
    (["--presets", "walking_xyz", "--modes", "static,fastest"], "fastest"),
    (["--sequences", "{tmp}", "--modes", "static"], "rgb.txt"),
    (["--sequences", "{tmp}/nothing", "--modes", "static"], "no such sequence folder or bag"),
    (["--presets", "walking_xyz", "--modes", "static", "--set", "tracking.no_such_key=3"], "no_such_key"),
    (["--presets", "walking_xyz", "--modes", "static", "--executor", "slurm"], "needs sbatch on PATH"),
])
def test_bad_arguments_fail_before_anything_runs(tmp_path, args, message):
    d = tmp_path / "sweep"
    args = [a.replace("{tmp}", str(tmp_path)) if isinstance(a, str) else a for a in args]
    import subprocess
    env = dict(os.environ, PATH=str(tmp_path))  # no Slurm client on this PATH
    r = subprocess.run([os.path.abspath(BIN), "sweep", "--out", str(d), *map(str, args)], capture_output=True,
                       text=True, env=env)
    assert r.returncode == 1, r.stdout + r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and message in lines[0], r.stderr
    assert not (d / "manifest.json").exists()


def test_the_report_page_shows_every_repeat(swept):
    from cli import page_data
    d, _ = swept
    lrdslam("report", d)
    data = page_data((d / "report.html").read_text())
    results = json.loads((d / "results.json").read_text())
    assert data["kind"] == "benchmark" and data["results"]["repeats"] is True
    runs = {(r["preset"], r["mode"]): r for r in data["results"]["runs"]}
    for e in results["entries"]:
        r = runs[(e["sequence"], e["mode"])]
        assert r["ate_rmse_runs"] == e["ate_rmse_m"]["runs"] and r["ate_m"]["rmse"] == e["ate_rmse_m"]["median"]
    # Each sequence's trajectories, read from its first complete repeat with the ground truth beside it.
    assert set(data["trajectories"]["walking_xyz"]["modes"]) == {"static", "geometric"}


def test_cells_of_another_binary_are_not_pooled(swept, tmp_path):
    import shutil
    d, _ = swept
    copy = tmp_path / "copy"
    shutil.copytree(d, copy)
    result = copy / "cells" / "walking_xyz__static__default__r1" / "result.json"
    record = json.loads(result.read_text())
    record["version"] = "0.0.9 (0123456789ab)"
    result.write_text(json.dumps(record))
    out = lrdslam("sweep", "collect", copy).stdout
    entries = [e for e in json.loads((copy / "results.json").read_text())["entries"]
               if (e["sequence"], e["mode"]) == ("walking_xyz", "static")]
    assert sorted(e["repeats"] for e in entries) == [1, 1]
    assert {e["version"] for e in entries} == {"0.0.9 (0123456789ab)", record_version(d)}
    assert "walking_xyz [0.0.9 (0123456789ab)" in out  # its own row, marked with the version


def record_version(d):
    record = json.loads((d / "cells" / "walking_xyz__static__default__r0" / "result.json").read_text())
    return record["version"]
