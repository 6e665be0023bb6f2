"""Events on the publisher's thread with the GIL handled; arrays shared, not copied; bad input as
exceptions."""
import sys
import threading
import time

import numpy as np
import pytest

import lrdslam


@pytest.fixture(scope="module")
def frames(walking):
    seq = lrdslam.io.read_sequence(walking)
    return [seq[i] for i in range(40)]


def test_events_arrive_in_order(walking, frames):
    seen = []
    slam = lrdslam.System(sequence=walking, mode="geometric")
    slam.subscribe(lambda e: seen.append(e))
    for f in frames:
        slam.track_rgbd(f.rgb, f.depth, f.timestamp)
    slam.shutdown()
    frame_events = [e for e in seen if e.kind == "frame"]
    assert [e.frame_id for e in frame_events] == list(range(len(frames)))
    assert [e.timestamp for e in frame_events] == [f.timestamp for f in frames]
    keyframes = [e for e in seen if e.kind == "keyframe"]
    assert len(keyframes) >= 2 and keyframes[0].frame_id == 0
    # A keyframe's event comes after its frame's? No: before the events its processing causes.
    first_map = next(i for i, e in enumerate(seen) if e.kind == "map")
    assert seen.index(keyframes[0]) < first_map
    assert frame_events[-1].pose.shape == (4, 4) and frame_events[-1].state == "ok"
    assert frame_events[-1].grey.shape == frames[0].rgb.shape[:2]


def test_a_raising_callback_is_reported_once_and_delivery_goes_on(walking, frames, monkeypatch):
    reports, calls = [], []
    monkeypatch.setattr(sys, "unraisablehook", lambda u: reports.append(u))

    def callback(event):
        calls.append(event.kind)
        raise ValueError("callback failed on purpose")

    slam = lrdslam.System(sequence=walking, mode="geometric")
    slam.subscribe(callback)
    states = [slam.track_rgbd(f.rgb, f.depth, f.timestamp).state for f in frames[:20]]
    slam.shutdown()
    assert states.count("ok") >= 18
    assert calls.count("frame") == 20
    assert len(reports) == 1 and isinstance(reports[0].exc_value, ValueError)


def test_a_slow_callback_does_not_hold_tracking_and_other_threads_run(walking, frames):
    delivered = []

    def slow(event):
        if event.kind == "frame":
            time.sleep(0.03)
            delivered.append(event.frame_id)

    ticks, stop = [], threading.Event()

    def ticker():  # a Python thread that needs the GIL
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    slam = lrdslam.System(sequence=walking, mode="geometric")
    slam.subscribe(slow)
    thread = threading.Thread(target=ticker)
    thread.start()
    inside = []  # (start, end) of each track_rgbd call
    for f in frames:
        t0 = time.perf_counter()
        slam.track_rgbd(f.rgb, f.depth, f.timestamp)
        inside.append((t0, time.perf_counter()))
    slam.shutdown()
    stop.set()
    thread.join()
    assert delivered == list(range(len(frames)))  # every frame, in order, after the fact
    # Tracking went on while the callback slept: events queued up behind it.
    assert slam.publisher_stats["max_queued"] >= 5
    # The ticker ran while the main thread was inside track_rgbd (the GIL was released).
    during = sum(1 for t in ticks if any(a < t < b for a, b in inside))
    assert during >= 5


def test_inputs_are_wrapped_not_copied(frames):
    rgb = np.ascontiguousarray(frames[0].rgb)
    assert lrdslam._core._image_address(rgb) == rgb.ctypes.data
    big = np.zeros((500, 700, 3), np.uint8)
    window = big[10:490, 30:670]  # rows of a larger image: OpenCV addresses them in place
    assert lrdslam._core._image_address(window) == window.ctypes.data
    flipped = rgb[:, ::-1]  # negative strides: copied once
    assert lrdslam._core._image_address(flipped) != flipped.ctypes.data
    # Outputs are views on the library's buffers.
    f = frames[1]
    assert not f.rgb.flags.owndata and f.rgb.base is not None
    assert f.rgb.ctypes.data == f.rgb.ctypes.data  # same frame object, same buffer each time


def test_result_mask_is_a_view(walking, frames):
    slam = lrdslam.System(sequence=walking, mode="geometric")
    masks = []
    for f in frames[:25]:
        r = slam.track_rgbd(f.rgb, f.depth, f.timestamp)
        if r.mask is not None:
            masks.append(r)
    slam.shutdown()
    assert masks, "the geometry check flagged no pixel in 25 frames of walking people"
    r = masks[-1]
    assert r.mask.dtype == np.uint8 and r.mask.shape == frames[0].rgb.shape[:2]
    assert not r.mask.flags.owndata and r.mask.ctypes.data == r.mask.ctypes.data
    assert (r.mask > 0).sum() > 0


def test_bad_arrays_are_exceptions(walking, frames):
    f = frames[0]
    slam = lrdslam.System(sequence=walking, mode="static")
    cases = [
        (lambda: slam.track_rgbd(f.rgb.astype(np.float64), f.depth, 1.0), "expected dtype uint8, got float64"),
        (lambda: slam.track_rgbd(np.zeros((480, 640, 4), np.uint8), f.depth, 1.0), "got shape (480x640x4)"),
        (lambda: slam.track_rgbd(f.rgb, f.depth.astype(np.int32), 1.0), "expected dtype float32, got int32"),
        (lambda: slam.track_rgbd(f.rgb[:240], f.depth[:240], 1.0), "colour image is 640x240"),
        (lambda: slam.track_rgbd("not an image", f.depth, 1.0), "expected a numpy array, got str"),
        (lambda: slam.track_rgbd(f.rgb, f.depth, 1.0, order="rbg"), "order must be 'rgb' or 'bgr'"),
    ]
    for call, message in cases:
        with pytest.raises(lrdslam.Error, match=message.replace("(", r"\(").replace(")", r"\)")):
            call()
    slam.track_rgbd(f.rgb, f.depth, 5.0)
    with pytest.raises(lrdslam.Error, match="does not increase"):
        slam.track_rgbd(f.rgb, f.depth, 4.0)
    slam.shutdown()
    with pytest.raises(lrdslam.Error, match="shut down"):
        slam.track_rgbd(f.rgb, f.depth, 6.0)


def test_bad_configuration_is_an_exception(walking, tmp_path):
    with pytest.raises(lrdslam.Error, match="config dict.*tracking.no_such_key|no_such_key"):
        lrdslam.System({"tracking": {"no_such_key": 1}}, sequence=walking)
    with pytest.raises(lrdslam.Error, match="missing.onnx"):
        lrdslam.System(sequence=walking, mode="semantic", segmenter="espnetv2-voc",
                       segmenter_model=tmp_path / "missing.onnx")
    with pytest.raises(lrdslam.Error, match="unknown segmenter"):
        lrdslam.System(sequence=walking, mode="semantic", segmenter="nope")
    with pytest.raises(lrdslam.Error, match="no such sequence folder or bag"):
        lrdslam.io.read_sequence(tmp_path / "nowhere")
    with pytest.raises(lrdslam.Error, match="expected a TUM trajectory file or an N x 8 array"):
        lrdslam.eval.ate(np.zeros((5, 7)), np.zeros((5, 8)))
    # A dict config is read as a file would be: the camera it names is the system's.
    slam = lrdslam.System({"camera": {"preset": "tum1"}})
    assert slam.camera["fx"] == pytest.approx(517.306408) and slam.camera_source.startswith("config")
    slam.shutdown()
