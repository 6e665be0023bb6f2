"""The Bonn-style presets through `lrdslam run`: on a 4-s prefix of each, `full` with the shipped
segmenter loses no frame and stays within 2 cm ATE, and `geometric` alone (no segmentation)
catches the thrown balloon and the carried box, which no person-class network knows."""
import json

import pytest

from cli import lrdslam, synth_input

PREFIX = 180  # 6 s: the balloon is thrown, the box lifted and carried
FULL_FRAMES = 120  # what `full` is judged on (CI time under the sanitizers)


@pytest.fixture(scope="module")
def sequences(tmp_path_factory):
    root = tmp_path_factory.mktemp("bonn")
    made = {}

    def get(preset):
        if preset not in made:
            made[preset] = root / preset
            synth_input("--preset", preset, "--frames", PREFIX, "--out", made[preset])
        return made[preset]

    return get


def run(seq, out, *extra):
    lrdslam("run", "--sequence", seq, "--out", out, "--quiet", "--deterministic", *extra)
    return json.loads((out / "summary.json").read_text())


@pytest.mark.parametrize("preset", ["crowd", "person_tracking", "moving_box", "moving_box_obstructing",
                                    "balloon", "synchronous"])
def test_full_tracks_every_frame_within_two_centimetres(sequences, tmp_path, preset):
    s = run(sequences(preset), tmp_path / "full", "--mode", "full", "--max-frames", FULL_FRAMES)
    assert s["frames"] == FULL_FRAMES
    assert s["lost"] == 0
    assert s["ate"]["rmse"] < 0.02, s["ate"]
    flags = s["dynamic_flags"]
    assert flags["recall"] > 0.9, flags
    assert flags["person_keypoints"] > 0


def test_geometry_alone_catches_the_balloon(sequences, tmp_path):
    s = run(sequences("balloon"), tmp_path / "geometric", "--mode", "geometric")
    flags = s["dynamic_flags"]
    assert flags["balloon_keypoints"] > 100, flags
    assert flags["balloon_recall"] >= 0.9, flags
    assert s["segmentation"] == "none" or "none" in str(s["segmentation"])


def test_geometry_alone_catches_the_carried_box(sequences, tmp_path):
    s = run(sequences("moving_box"), tmp_path / "geometric", "--mode", "geometric")
    flags = s["dynamic_flags"]
    assert flags["moved_object_keypoints"] > 50, flags
    assert flags["moved_object_recall"] >= 0.9, flags
