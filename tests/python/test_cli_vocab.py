"""`lrdslam vocab train|info` and `lrdslam synth --blank`: a vocabulary trained from a folder of
images is deterministic and usable by `run`; bad input gives one-line errors."""
import json

import pytest

from cli import lrdslam, synth_input


@pytest.fixture(scope="module")
def images(tmp_path_factory):
    d = tmp_path_factory.mktemp("voc")
    synth_input("--export-voc", d, "--images", 6, "--seed", 7000)
    return d / "JPEGImages"


def test_train_is_deterministic_and_info_reads_it(images, tmp_path):
    files = []
    for k in range(2):
        f = tmp_path / f"v{k}.lrdv"
        r = lrdslam("vocab", "train", "--images", images, "--out", f, "--levels", 3, "--features", 500)
        assert "words" in r.stdout
        files.append(f)
    assert files[0].read_bytes() == files[1].read_bytes()
    info = lrdslam("vocab", "info", files[0]).stdout
    assert "k 10, levels 3" in info


def test_train_from_a_list_file(images, tmp_path):
    listed = sorted(images.glob("*.jpg"))[:3]
    lst = tmp_path / "list.txt"
    lst.write_text("# three images\n" + "\n".join(str(p) for p in listed) + "\n")
    f = tmp_path / "l.lrdv"
    r = lrdslam("vocab", "train", "--images", lst, "--out", f, "--levels", 2)
    assert "3 used" in r.stdout or "images: 3" in r.stdout, r.stdout
    assert f.stat().st_size > 0


def test_train_without_images_fails_clearly(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    r = lrdslam("vocab", "train", "--images", empty, "--out", tmp_path / "x.lrdv", check=False)
    assert r.returncode != 0
    assert str(empty) in r.stderr


def test_info_on_a_missing_file_fails_clearly(tmp_path):
    r = lrdslam("vocab", "info", tmp_path / "missing.lrdv", check=False)
    assert r.returncode != 0 and "missing.lrdv" in r.stderr


@pytest.mark.parametrize("value", ["10", "5:0", "a:b", "-1:5"])
def test_synth_blank_needs_start_and_count(tmp_path, value):
    r = lrdslam("synth", "--preset", "static_xyz", "--frames", 3, "--blank", value, "--out", tmp_path / "s", check=False)
    assert r.returncode != 0 and "--blank" in r.stderr


def test_synth_blank_writes_black_frames_without_depth(tmp_path):
    import cv2

    out = tmp_path / "s"
    lrdslam("synth", "--preset", "static_xyz", "--frames", 4, "--blank", "1:2", "--out", out)
    meta = json.loads((out / "sequence.json").read_text())
    assert meta["blank"] == {"from": 1, "count": 2}
    rgb = sorted((out / "rgb").glob("*.png"))
    depth = sorted((out / "depth").glob("*.png"))
    for i in range(4):
        c = cv2.imread(str(rgb[i]), cv2.IMREAD_UNCHANGED)
        d = cv2.imread(str(depth[i]), cv2.IMREAD_UNCHANGED)
        blank = i in (1, 2)
        assert (c.max() == 0) == blank, i
        assert (d.max() == 0) == blank, i
