"""The HTML report in a real browser (docs/report.md): Debian's headless Chromium opens the page of
a short run from a file:// URL with the network off; the test fails on any console message (an
uncaught error, a resource that did not load), checks that every chart the page promises was drawn,
and that each chart's, map's and sample frame's region of a screenshot is not blank."""
import json
import re
import shutil
import subprocess

import cv2
import numpy as np
import pytest

from cli import lrdslam, synth_input

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
WINDOW = (1000, 16000)
CHARTS = {"trajectory-top", "trajectory-side", "ape-over-time", "flags-over-time", "stage-times", "time-distribution",
          "map3d-oblique", "map3d-top", "map3d-side"}


def chromium(profile, *args):
    """Headless Chromium (no sandbox: the tests may run as root), its console on stderr."""
    if CHROMIUM is None:
        pytest.skip("chromium is not installed (scripts/install-deps.sh installs it)")
    # --enable-unsafe-swiftshader: WebGL (the 3-D map) on the CPU without a deprecation warning.
    cmd = [CHROMIUM, "--headless=new", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader", "--disable-dev-shm-usage", "--hide-scrollbars", "--mute-audio",
           "--no-first-run", "--disable-extensions", "--proxy-server=127.0.0.1:9", "--proxy-bypass-list=<-loopback>",
           "--force-device-scale-factor=1", f"--window-size={WINDOW[0]},{WINDOW[1]}", f"--user-data-dir={profile}",
           "--enable-logging=stderr", "--v=0", "--virtual-time-budget=15000", *map(str, args)]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=300)


def console_messages(stderr):
    """Every console line but the software GL driver's performance notes (the screenshot reads the
    WebGL canvases back: "GPU stall due to ReadPixels"), which are not the page's errors."""
    return [l for l in stderr.splitlines() if ("CONSOLE" in l or "Failed to load" in l or "Uncaught" in l)
            and "GL Driver Message (OpenGL, Performance," not in l]


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    d = tmp_path_factory.mktemp("browser")
    synth_input("--preset", "walking_xyz", "--frames", 50, "--out", d / "seq")
    lrdslam("run", "--sequence", d / "seq", "--mode", "geometric", "--dense", "--quiet", "--out", d / "out", "--report")
    dom, shot = open_in_chromium(d, d / "out" / "report.html")
    return d, dom, shot


def open_in_chromium(d, html):
    """The page's DOM once its scripts ran, and a screenshot (d/shot.png) of the window."""
    url = html.resolve().as_uri()
    return chromium(d / "profile", "--dump-dom", url), chromium(d / "profile", f"--screenshot={d / 'shot.png'}", url)


def assert_ready_without_console_messages(dom, shot, charts):
    assert dom.returncode == 0 and shot.returncode == 0, dom.stderr[-2000:] + shot.stderr[-2000:]
    assert console_messages(dom.stderr) == [] and console_messages(shot.stderr) == []
    body = re.search(r"<body([^>]*)>", dom.stdout).group(1)
    assert 'data-report-ready="true"' in body, dom.stdout[:2000]
    assert set(re.search(r'data-charts="([^"]*)"', body).group(1).split()) == charts
    # uPlot drew a canvas into each chart's figure.
    for chart in charts:
        figure = re.search(rf'<figure class="chart[^"]*" id="{chart}".*?</figure>', dom.stdout, re.S)
        assert figure and "<canvas" in figure.group(0), chart


def assert_figures_drawn(d, dom, count):
    """Each figure's region of the screenshot (the page records where it put them) holds ink and colour."""
    shot = cv2.imread(str(d / "shot.png"), cv2.IMREAD_COLOR)
    assert shot is not None and shot.shape[1] == WINDOW[0]
    boxes = re.findall(r'<figure class="(chart|chart map3d|image|image sample|image repair)"[^>]*data-box="(\d+),(\d+),(\d+),(\d+)"', dom.stdout)
    assert len(boxes) == count
    for kind, *box in boxes:
        x, y, w, h = map(int, box)
        assert y + h <= shot.shape[0], ("the page is longer than the screenshot window", box)
        region = shot[y:y + h, x:x + w].reshape(-1, 3)
        ink = np.count_nonzero(np.abs(region.astype(int) - 255).sum(axis=1) > 60) / len(region)
        colours = len(np.unique(region // 16, axis=0))
        assert ink > 0.02 and colours > 12, (kind, box, ink, colours)
        # Charts carry their series' colours, not only black axes and text.
        hsv = cv2.cvtColor(region.reshape(1, -1, 3), cv2.COLOR_BGR2HSV).reshape(-1, 3)
        assert np.count_nonzero((hsv[:, 1] > 80) & (hsv[:, 2] > 60)) > 200, (kind, box)


def test_the_page_opens_without_a_console_message_and_draws_every_chart(page):
    d, dom, shot = page
    assert_ready_without_console_messages(dom, shot, CHARTS)
    # The images are the run's, inline.
    srcs = re.findall(r'<img[^>]* src="([^"]*)"', dom.stdout)
    frames = json.loads((d / "out" / "report_frames" / "frames.json").read_text())
    assert len(srcs) == 2 + len(frames["frames"]) + len(frames["repairs"])
    assert all(s.startswith("data:image/png;base64,") or s.startswith("data:image/jpeg;base64,") for s in srcs)
    summary = json.loads((d / "out" / "summary.json").read_text())
    assert f"{100 * summary['ate']['rmse']:.3f}" in dom.stdout  # the ATE table
    assert re.search(r"Median total [0-9.]+ ms = [0-9.]+ Y, where Y = [0-9.]+ ms", dom.stdout)


def test_each_chart_and_image_is_drawn_in_the_screenshot(page):
    d, dom, _ = page
    frames = json.loads((d / "out" / "report_frames" / "frames.json").read_text())
    samples, repairs = frames["frames"], frames["repairs"]
    assert len(samples) > 0 and len(repairs) > 0
    assert_figures_drawn(d, dom, len(CHARTS) + 2 + len(samples) + len(repairs))


def test_the_benchmark_page_draws_its_tables_and_every_presets_trajectories(benchmark_folder, tmp_path):
    lrdslam("report", benchmark_folder, "--out", tmp_path / "benchmark.html")
    dom, shot = open_in_chromium(tmp_path, tmp_path / "benchmark.html")
    results = json.loads((benchmark_folder / "results.json").read_text())
    charts = {"ate-by-preset"} | {f"trajectory-{p}" for p in results["presets"]}
    assert_ready_without_console_messages(dom, shot, charts)
    # Tables 4-7 and 10 and eta, with the runs' figures.
    for title in ("Tables 4-5: ATE", "Table 6: RPE translation", "Table 7: RPE rotation", "Time per frame (Table 10)",
                  "Improvement over static"):
        assert title in dom.stdout, title
    for r in results["runs"]:
        assert f"{100 * r['ate_m']['rmse']:.2f}" in dom.stdout
        assert f"{r['time_ms']['median']:.1f} ({r['time_y']['median']:.2f} Y)" in dom.stdout
        if "eta_percent" in r:
            assert f"{r['eta_percent']['ate_rmse']:.1f} / " in dom.stdout
    assert_figures_drawn(tmp_path, dom, len(charts))
