"""Issue 22 item 4: a corpus of bad inputs, generated at test time from one valid synthetic sequence.

Each case copies what it needs of a 12-frame `walking_xyz` render (images as symbolic links, so a
case costs a few kilobytes), applies ONE corruption and runs `lrdslam run` on it (under ctest the
binary is the AddressSanitizer + UBSan build). The contract for every case:

  * a non-zero exit status, and not a signal;
  * stderr is exactly one line, `error: ...`, that names the offending file (its basename is
    enough) - spdlog lines, if any reach stderr, are not counted;
  * no sanitizer report, no `terminate called`, no segmentation fault, no hang.

The families: PNG images (truncated, bit-flipped, garbage, wrong bit depth / channel count,
colour/depth size mismatch, a header claiming 100000 x 100000 pixels, a real 20000 x 20000
image), the list files (rgb.txt, depth.txt, associations.txt, groundtruth.txt: garbage, wrong
field counts, bad numbers, duplicate and unsorted lines, empty, binary), ORB-SLAM settings and
lrd-slam config files (NaN, negative, zero and huge values, syntax errors, unknown and duplicate
keys), vocabularies and ONNX models (empty, truncated, bit-flipped, wrong magic), ground-truth
mask folders, and folders that are empty, missing or files.

"Unreadable" files: the tests run as root in CI, and `chmod 000` does not stop root from reading
a file, so unreadability is made with things no user can read as a regular file: a directory
where the file should be, a dangling symbolic link and a symbolic link that points to itself
(ELOOP). FIFOs are not used: opening one for reading blocks until a writer appears.

Cases that show a known lrdslam bug are marked xfail(strict=True) with the reason; when the bug
is fixed the case passes and strict xfail makes the suite fail, so the marker gets removed.
The module prints "bad-input corpus: N cases, P passed, X xfailed (known bugs)" at the end.
"""
import contextlib
import os
import re
import shutil
import struct
import subprocess
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Optional

import cv2
import numpy as np
import pytest

from cli import BIN, synth_input

FRAMES = 12
TIMEOUT_S = 120  # a hang is a failure, not a stuck suite

# Anything here on stdout or stderr is a crash report, whatever the exit status says.
CRASH_MARKS = ("AddressSanitizer", "LeakSanitizer", "UndefinedBehaviorSanitizer", "runtime error:",
               "ThreadSanitizer", "terminate called", "Segmentation fault", "core dumped", "Aborted")
# spdlog's default pattern: "[2026-12-02 02:28:21.393] [warning] ..."
SPDLOG_LINE = re.compile(r"^\[\d{4}-\d\d-\d\d [\d:.]+\] \[\w+\]")

# ---------------------------------------------------------------------------------------------
# The case registry


@dataclass
class Case:
    id: str
    prepare: Callable  # (Ctx) -> (extra CLI arguments, text the error line must contain)
    bug: Optional[str] = None  # a known lrdslam bug: the case is xfail(strict=True)


CASES: list = []


def case(id_, prepare, bug=None):
    CASES.append(Case(id_, prepare, bug))


# ---------------------------------------------------------------------------------------------
# Files


def replace(path: Path, data) -> Path:
    """Puts `data` (bytes or str) at `path`, replacing a link, file or folder there (never writing
    through a link into the shared base sequence)."""
    remove(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(data.encode() if isinstance(data, str) else data)
    return path


def remove(path: Path):
    if path.is_symlink() or path.is_file():
        path.unlink()
    elif path.is_dir():
        shutil.rmtree(path)


def make_dir(path: Path) -> Path:
    """A folder where a file should be."""
    remove(path)
    path.mkdir(parents=True)
    (path / "inside.txt").write_text("a folder, not a file\n")
    return path


def make_dangling(path: Path) -> Path:
    remove(path)
    os.symlink(path.parent / "no-such-target", path)
    return path


def make_loop(path: Path) -> Path:
    """A symbolic link to itself: open() fails with ELOOP (unreadable even for root)."""
    remove(path)
    os.symlink(path.name, path)
    return path


def flip(data: bytes, offset: int, bit: int = 0) -> bytes:
    b = bytearray(data)
    b[offset] ^= 1 << bit
    return bytes(b)


def garbage(n: int, seed: int = 7) -> bytes:
    return np.random.default_rng(seed).integers(0, 256, n, dtype=np.uint8).tobytes()


# PNG pieces, for corruptions that must land in a specific chunk.
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def png_chunk(ctype: bytes, payload: bytes) -> bytes:
    return struct.pack(">I", len(payload)) + ctype + payload + struct.pack(">I", zlib.crc32(ctype + payload))


def png_chunks(data: bytes):
    """(type, offset of the payload, length) of each chunk."""
    out, pos = [], 8
    while pos + 8 <= len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        out.append((data[pos + 4:pos + 8], pos + 8, length))
        pos += 12 + length
    return out


def png_offset(data: bytes, ctype: bytes, within: float = 0.5) -> int:
    """Offset of a byte `within` the first `ctype` chunk's payload."""
    for t, off, length in png_chunks(data):
        if t == ctype:
            return off + int(length * within)
    raise AssertionError(f"no {ctype} chunk")


def raw_png(width: int, height: int, bit_depth: int, colour_type: int, idat: bytes) -> bytes:
    ihdr = struct.pack(">IIBBBBB", width, height, bit_depth, colour_type, 0, 0, 0)
    return PNG_SIGNATURE + png_chunk(b"IHDR", ihdr) + png_chunk(b"IDAT", idat) + png_chunk(b"IEND", b"")


def huge_grey_png(width: int, height: int) -> bytes:
    """A black 8-bit grey PNG, compressed row by row (a 20000 x 20000 one is about 0.4 MB)."""
    co = zlib.compressobj(9)
    row = b"\0" * (width + 1)  # filter byte + pixels
    parts = [co.compress(row) for _ in range(height)]
    parts.append(co.flush())
    return raw_png(width, height, 8, 0, b"".join(parts))


def grey_alpha_png(depth: np.ndarray) -> bytes:
    """16-bit grey + alpha (PNG colour type 4), which cv2.imencode cannot write."""
    h, w = depth.shape
    px = np.stack([depth, np.full_like(depth, 65535)], axis=-1).astype(">u2").reshape(h, w * 2)
    rows = np.concatenate([np.zeros((h, 1), np.uint8), px.view(np.uint8)], axis=1)  # filter byte 0
    return raw_png(w, h, 16, 4, zlib.compress(rows.tobytes()))


def encode_png(img: np.ndarray) -> bytes:
    ok, buf = cv2.imencode(".png", img)
    assert ok
    return buf.tobytes()


# ---------------------------------------------------------------------------------------------
# Per-case context


class Ctx:
    def __init__(self, base: Path, tmp: Path, frames, big_png: Callable):
        self.base = base  # the valid sequence; never written to
        self.tmp = tmp
        self.frames = frames  # [(rgb relative path, depth relative path)] from associations.txt
        self.big_png = big_png
        self.sequence = base  # what --sequence gets
        self.max_frames = 2
        self.seq: Optional[Path] = None

    def copy_seq(self, associations=True, masks=False) -> Path:
        """A private copy of the sequence: list and settings files copied, images linked."""
        d = self.tmp / "seq"
        d.mkdir()
        names = ["rgb.txt", "depth.txt", "groundtruth.txt", "settings.yaml", "sequence.json"]
        if associations:
            names.append("associations.txt")
        for name in names:
            shutil.copyfile(self.base / name, d / name)
        for sub in ["rgb", "depth"] + (["mask"] if masks else []):
            (d / sub).mkdir()
            for f in (self.base / sub).iterdir():
                os.symlink(f, d / sub / f.name)
        self.seq = self.sequence = d
        return d

    def rgb(self, i=0) -> Path:
        return self.seq / self.frames[i][0]

    def depth(self, i=0) -> Path:
        return self.seq / self.frames[i][1]

    def read(self, rel) -> bytes:
        return (self.base / rel).read_bytes()

    def image(self, rel, flags=cv2.IMREAD_UNCHANGED) -> np.ndarray:
        return cv2.imread(str(self.base / rel), flags)

    def edit_lines(self, name: str, edit: Callable) -> Path:
        """Rewrites list file `name` of the copy: edit(list of lines) -> list of lines."""
        p = self.seq / name
        lines = p.read_text().splitlines()
        return replace(p, "\n".join(edit(lines)) + "\n")


def data_lines(lines):
    """Indices of the non-comment lines."""
    return [k for k, l in enumerate(lines) if l.strip() and not l.startswith("#")]


# ---------------------------------------------------------------------------------------------
# 1. Images. Frame 0 unless the case says otherwise (frame 2 with --max-frames 3: the error comes
# while the tracker and the mapper are running).

def image_case(id_, which, corrupt, frame=0, bug=None):
    """corrupt(ctx, path, original bytes) writes the bad file."""

    def prepare(ctx):
        ctx.copy_seq()
        path = ctx.rgb(frame) if which == "rgb" else ctx.depth(frame)
        corrupt(ctx, path, ctx.read(ctx.frames[frame][0 if which == "rgb" else 1]))
        ctx.max_frames = frame + 1
        return [], path.name

    case(id_, prepare, bug)


IMAGE_CORRUPTIONS = {
    # id: (corrupt(ctx, path, original bytes), libpng complains on stderr)
    "png-empty": (lambda c, p, d: replace(p, b""), False),
    "png-truncated-half": (lambda c, p, d: replace(p, d[:len(d) // 2]), True),
    "png-bitflip-ihdr": (lambda c, p, d: replace(p, flip(d, png_offset(d, b"IHDR", 0.1), 2)), True),
    "png-bitflip-idat": (lambda c, p, d: replace(p, flip(d, png_offset(d, b"IDAT", 0.5), 5)), True),
    "png-zero-width": (lambda c, p, d: replace(p, raw_png(0, 480, 8, 0, zlib.compress(b"\0"))), True),
    "png-header-claims-100000x100000":
        (lambda c, p, d: replace(p, raw_png(100000, 100000, 8, 0, zlib.compress(b"\0" * 100001))), False),
    "random-bytes": (lambda c, p, d: replace(p, garbage(5000)), False),
    "is-a-directory": (lambda c, p, d: make_dir(p), False),
    "symlink-loop": (lambda c, p, d: make_loop(p), False),
}
RGB_SUBSET = ["png-empty", "png-truncated-half", "png-bitflip-idat", "png-zero-width",
              "png-header-claims-100000x100000", "random-bytes", "is-a-directory", "symlink-loop"]
DEPTH_SUBSET = ["png-truncated-half", "png-bitflip-ihdr", "is-a-directory"]
for id_ in RGB_SUBSET:
    image_case(f"rgb-{id_}", "rgb", IMAGE_CORRUPTIONS[id_][0])
for id_ in DEPTH_SUBSET:
    image_case(f"depth-{id_}", "depth", IMAGE_CORRUPTIONS[id_][0])

# mid-run: the third frame is bad while the map is being built
image_case("rgb-frame2-truncated", "rgb", lambda c, p, d: replace(p, d[:len(d) // 3]), frame=2)
image_case("depth-frame2-bitflip-idat", "depth",
           lambda c, p, d: replace(p, flip(d, png_offset(d, b"IDAT", 0.3), 1)), frame=2)

# wrong bit depth / channel count of the depth image (must be 16-bit single channel)
image_case("depth-8bit-grey", "depth",
           lambda c, p, d: replace(p, encode_png((c.image(c.frames[0][1]) // 256).astype(np.uint8))))
image_case("depth-16bit-3-channel", "depth",
           lambda c, p, d: replace(p, encode_png(cv2.merge([c.image(c.frames[0][1])] * 3))))
image_case("depth-16bit-grey-alpha", "depth", lambda c, p, d: replace(p, grey_alpha_png(c.image(c.frames[0][1]))))

# colour / depth size mismatch
image_case("rgb-half-size", "rgb",
           lambda c, p, d: replace(p, encode_png(cv2.resize(c.image(c.frames[0][0]), (320, 240)))))
image_case("depth-transposed", "depth",
           lambda c, p, d: replace(p, encode_png(np.ascontiguousarray(c.image(c.frames[0][1]).T))))
# 1.2 GB once decoded; the loader must reject it (here: it does not match the 640x480 depth image)
image_case("rgb-20000x20000", "rgb", lambda c, p, d: replace(p, c.big_png()))


def both_half_size(ctx):
    # colour and depth agree with each other, not with the 640x480 camera of settings.yaml
    ctx.copy_seq()
    replace(ctx.rgb(), encode_png(cv2.resize(ctx.image(ctx.frames[0][0]), (320, 240))))
    replace(ctx.depth(), encode_png(cv2.resize(ctx.image(ctx.frames[0][1]), (320, 240),
                                               interpolation=cv2.INTER_NEAREST)))
    return [], ctx.rgb().name


case("rgb-and-depth-half-size-vs-camera", both_half_size)

# ---------------------------------------------------------------------------------------------
# 2. List files. associations.txt is used when present; the rgb.txt / depth.txt cases remove it.


def replace_line(k, new):
    """Edit: data line k (counted from 0) becomes new(old line)."""
    return lambda L, D: L[:D[k]] + [new(L[D[k]])] + L[D[k] + 1:]


def first_field(text):
    return lambda l: " ".join([text] + l.split()[1:])


TS_EDITS = {
    # name: edit(lines, data line indices) -> lines
    "garbage-line": lambda L, D: L[:D[3]] + ["!@#$ this is %% not a line &&"] + L[D[3]:],
    "one-field": replace_line(2, lambda l: l.split()[0]),
    "timestamp-nan": replace_line(1, first_field("nan")),
    "timestamp-inf": lambda L, D: replace_line(len(D) - 1, first_field("inf"))(L, D),
    "timestamp-trailing-junk": replace_line(1, lambda l: l.split()[0] + "x " + " ".join(l.split()[1:])),
    "timestamp-1000-digits": replace_line(1, first_field("9" * 1000)),
    "duplicate-line": lambda L, D: L[:D[4]] + [L[D[4]]] + L[D[4]:],
    "unsorted-lines": lambda L, D: L[:D[4]] + [L[D[5]], L[D[4]]] + L[D[5] + 1:],
    "empty": lambda L, D: [],
    "comments-only": lambda L, D: ["# nothing here", "#"],
    "utf8-bom": replace_line(0, lambda l: "\ufeff" + l),
    "nul-byte": replace_line(2, lambda l: l.replace(" ", " \0", 1)),
}
LIST_EDITS = {
    "associations.txt": ["garbage-line", "timestamp-nan", "timestamp-1000-digits", "duplicate-line",
                         "unsorted-lines", "empty", "utf8-bom", "nul-byte"],
    "rgb.txt": ["garbage-line", "timestamp-trailing-junk", "duplicate-line"],
    "depth.txt": ["one-field", "timestamp-inf", "unsorted-lines", "comments-only"],
}


def list_case(name, edit_id, edit, bug=None):
    def prepare(ctx):
        ctx.copy_seq(associations=name == "associations.txt")
        ctx.edit_lines(name, lambda L: edit(L, data_lines(L)))
        return [], name

    case(f"{name}-{edit_id}", prepare, bug)


for name, edit_ids in LIST_EDITS.items():
    for edit_id in edit_ids:
        list_case(name, edit_id, TS_EDITS[edit_id])


def list_binary(ctx):
    ctx.copy_seq()
    replace(ctx.seq / "associations.txt", garbage(3000, seed=1))
    return [], "associations.txt"


case("associations.txt-binary-garbage", list_binary)


def list_points_at(name, what):
    """The first listed image is missing / a folder / a dangling link."""

    def prepare(ctx):
        ctx.copy_seq(associations=name == "associations.txt")
        target = ctx.seq / ctx.frames[0][1 if name == "depth.txt" else 0]
        {"missing": remove, "folder": make_dir, "dangling": make_dangling}[what](target)
        return [], name

    return prepare


case("associations.txt-lists-a-missing-image", list_points_at("associations.txt", "missing"))
case("rgb.txt-lists-a-missing-image", list_points_at("rgb.txt", "missing"))
case("depth.txt-lists-a-dangling-link", list_points_at("depth.txt", "dangling"))


def no_association(ctx):
    # depth timestamps 100 s later: no colour image has a depth image within 0.02 s
    ctx.copy_seq(associations=False)

    def shift(L):
        out = []
        for l in L:
            if l.startswith("#") or not l.strip():
                out.append(l)
            else:
                t, f = l.split()
                out.append(f"{float(t) + 100:.6f} {f}")
        return out

    ctx.edit_lines("depth.txt", shift)
    return [], "rgb.txt"


case("depth.txt-no-timestamp-matches-rgb", no_association)


def list_file_is(name, what, bug=None):
    def prepare(ctx):
        ctx.copy_seq(associations=name == "associations.txt")
        p = ctx.seq / name
        {"missing": remove, "folder": make_dir, "dangling": make_dangling, "loop": make_loop}[what](p)
        if name == "associations.txt":
            # without rgb.txt / depth.txt to fall back on
            remove(ctx.seq / "rgb.txt")
            remove(ctx.seq / "depth.txt")
        return [], name

    case(f"{name}-is-{what}", prepare, bug)


list_file_is("rgb.txt", "missing")
list_file_is("depth.txt", "dangling")
list_file_is("rgb.txt", "folder")
list_file_is("associations.txt", "folder")

# groundtruth.txt is read after the run (2 frames tracked, so the trajectory can be compared).
# Unsorted lines are not an error there: TUM's evaluate_ate.py sorts them, and so does lrdslam.
GT_EDITS = {
    "garbage-line": lambda L, D: L[:D[3]] + ["garbage garbage"] + L[D[3]:],
    "infinite-value": replace_line(2, lambda l: " ".join(l.split()[:1] + ["inf"] + l.split()[2:])),
    "duplicate-line": lambda L, D: L[:D[4]] + [L[D[4]]] + L[D[4]:],
}


def gt_case(edit_id, edit):
    def prepare(ctx):
        ctx.copy_seq()
        ctx.edit_lines("groundtruth.txt", lambda L: edit(L, data_lines(L)))
        return [], "groundtruth.txt"

    case(f"groundtruth.txt-{edit_id}", prepare)


for edit_id, edit in GT_EDITS.items():
    gt_case(edit_id, edit)


def gt_folder(ctx):
    ctx.copy_seq()
    make_dir(ctx.seq / "groundtruth.txt")
    return [], "groundtruth.txt"


case("groundtruth.txt-is-a-folder", gt_folder)

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

# ---------------------------------------------------------------------------------------------
# 5. Vocabulary (header: 8-byte magic, u32 version, k, levels, nodes, words; 48-byte nodes)

VOCAB = Path(__file__).resolve().parents[2] / "vocab" / "orb_vocab.lrdv"
HEADER, NODE = 28, 48
VOCAB_EDITS = {
    "empty": lambda d: b"",
    "truncated-half": lambda d: d[:len(d) // 2],
    "one-byte-appended": lambda d: d + b"\0",
    "bitflip-magic": lambda d: flip(d, 0, 1),
    "bitflip-version": lambda d: flip(d, 8, 3),
    "levels-huge": lambda d: d[:16] + b"\xff\xff\xff\x7f" + d[20:],
    "bitflip-node-count": lambda d: flip(d, 23, 7),
    "node-weight-nan": lambda d: d[:HEADER + NODE + 40] + struct.pack("<d", float("nan")) + d[HEADER + 2 * NODE:],
    "node-parent-forward": lambda d: d[:HEADER + NODE * 5] + struct.pack("<I", 7) + d[HEADER + NODE * 5 + 4:],
}


def vocab_case(id_, make):
    def prepare(ctx):
        f = ctx.tmp / "bad.lrdv"
        make(f)
        return ["--vocabulary", f], f.name

    case(f"vocabulary-{id_}", prepare)


for id_, edit in VOCAB_EDITS.items():
    vocab_case(id_, lambda f, edit=edit: replace(f, edit(VOCAB.read_bytes())))
vocab_case("is-a-folder", make_dir)

# ---------------------------------------------------------------------------------------------
# 6. ONNX segmentation model (--mode semantic --segmenter fnet --segmenter-model FILE)

MODEL = Path(__file__).resolve().parents[2] / "models" / "fnet-lite.onnx"


def onnx_case(id_, make):
    def prepare(ctx):
        f = ctx.tmp / "bad.onnx"
        make(f)
        return ["--mode", "semantic", "--segmenter", "fnet", "--segmenter-model", f], f.name

    case(f"onnx-{id_}", prepare)


for id_, edit in {
    "empty": lambda d: b"",
    "truncated-half": lambda d: d[:len(d) // 2],
    "bitflip-first-tag": lambda d: flip(d, 0, 7),
}.items():
    onnx_case(id_, lambda f, edit=edit: replace(f, edit(MODEL.read_bytes())))
onnx_case("is-a-vocabulary", lambda f: replace(f, VOCAB.read_bytes()[:200000]))
onnx_case("is-a-folder", make_dir)

# ---------------------------------------------------------------------------------------------
# 7. Ground-truth mask folders (--mode semantic --segmenter gt-masks). --deterministic runs the
# segmentation in sync, so frame 0's mask is read before frame 0 is tracked; the async case reads a
# bad mask in the segmentation thread while tracking goes on.


def mask_case(id_, corrupt, bug=None, frame=0):
    def prepare(ctx):
        ctx.copy_seq(masks=True)
        target = corrupt(ctx, ctx.seq / "mask" / ctx.rgb(frame).name)
        args = ["--mode", "semantic", "--segmenter", "gt-masks"]
        if frame == 0:
            args.append("--deterministic")
        ctx.max_frames = frame + 2
        return args, target.name

    case(f"mask-{id_}", prepare, bug)


def mask_image(c, p):
    return cv2.imread(str(c.base / "mask" / p.name), cv2.IMREAD_UNCHANGED)


mask_case("folder-missing", lambda c, p: (remove(p.parent), p.parent)[1])
mask_case("folder-empty", lambda c, p: (shutil.rmtree(p.parent), p.parent.mkdir(), p.parent)[2])
mask_case("png-truncated", lambda c, p: replace(p, (c.base / "mask" / p.name).read_bytes()[:100]))
mask_case("png-16bit", lambda c, p: replace(p, encode_png(mask_image(c, p).astype(np.uint16))))
mask_case("png-half-size", lambda c, p: replace(p, encode_png(
    cv2.resize(mask_image(c, p), (320, 240), interpolation=cv2.INTER_NEAREST))))
mask_case("frame2-3-channel-async", lambda c, p: replace(p, encode_png(cv2.merge([mask_image(c, p)] * 3))), frame=2)

# ---------------------------------------------------------------------------------------------
# 8. Folders


def seq_missing(ctx):
    ctx.sequence = ctx.tmp / "no_such_sequence"
    return [], "no_such_sequence"


def seq_empty(ctx):
    ctx.sequence = ctx.tmp / "empty_sequence"
    ctx.sequence.mkdir()
    return [], "rgb.txt"


def seq_is_file(ctx):
    ctx.sequence = replace(ctx.tmp / "sequence_file", "not a folder\n")
    return [], "sequence_file"


def rgb_folder_missing(ctx):
    ctx.copy_seq()
    remove(ctx.seq / "rgb")
    return [], "associations.txt"


def depth_folder_empty(ctx):
    ctx.copy_seq(associations=False)
    shutil.rmtree(ctx.seq / "depth")
    (ctx.seq / "depth").mkdir()
    return [], "depth.txt"


def out_is_file(ctx):
    out = replace(ctx.tmp / "out_file", "a file where the output folder should be\n")
    return ["--out", out], "out_file"


def save_masks_is_file(ctx):
    f = replace(ctx.tmp / "masks_file", "x\n")
    return ["--save-masks", f], "masks_file"


case("folder-sequence-missing", seq_missing)
case("folder-sequence-empty", seq_empty)
case("folder-sequence-is-a-file", seq_is_file)
case("folder-rgb-missing", rgb_folder_missing)
case("folder-depth-empty", depth_folder_empty)
case("folder-out-is-a-file", out_is_file)
case("folder-save-masks-is-a-file", save_masks_is_file)

# ---------------------------------------------------------------------------------------------
# Fixtures, the check, the summary

RESULTS: dict = {}


@pytest.fixture(scope="session")
def base_sequence(tmp_path_factory):
    d = tmp_path_factory.mktemp("bad_input_base") / "walking_xyz"
    synth_input("--preset", "walking_xyz", "--frames", FRAMES, "--out", d)
    frames = []
    for line in (d / "associations.txt").read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            f = line.split()
            frames.append((f[1], f[3]))
    assert len(frames) == FRAMES
    return d, frames


@pytest.fixture(scope="session")
def big_png(tmp_path_factory):
    """20000 x 20000 PNG bytes, made once and only when a case asks for it."""
    cache = {}

    def get():
        if "png" not in cache:
            cache["png"] = huge_grey_png(20000, 20000)
        return cache["png"]

    return get


@pytest.fixture(scope="module", autouse=True)
def corpus_summary(request):
    yield
    if not RESULTS:
        return
    passed = sum(1 for ok, _ in RESULTS.values() if ok)
    xfailed = sum(1 for ok, bug in RESULTS.values() if not ok and bug)
    failed = len(RESULTS) - passed - xfailed
    line = f"bad-input corpus: {len(RESULTS)} cases, {passed} passed, {xfailed} xfailed (known bugs)"
    if failed:
        line += f", {failed} FAILED"
    # Past pytest's output capture (which would swallow it in a passing run), like capsys.disabled().
    capture = request.config.pluginmanager.get_plugin("capturemanager")
    reporter = request.config.pluginmanager.get_plugin("terminalreporter")
    with capture.global_and_fixture_disabled() if capture is not None else contextlib.nullcontext():
        if reporter is not None:
            reporter.write_line("")
            reporter.write_line(line)
        else:
            print(line, flush=True)


def problems_with(r, expect: str):
    """What breaks the contract, as a list of sentences (empty: the case passed)."""
    out = []
    if r.returncode < 0:
        out.append(f"killed by signal {-r.returncode}")
    elif r.returncode == 0:
        out.append("exit status 0")
    for mark in CRASH_MARKS:
        if mark in r.stderr or mark in r.stdout:
            out.append(f"'{mark}' in the output")
    lines = [l for l in r.stderr.splitlines() if l.strip() and not SPDLOG_LINE.match(l)]
    if len(lines) != 1:
        out.append(f"{len(lines)} lines on stderr, expected one")
    elif not lines[0].startswith("error: "):
        out.append("the stderr line does not start with 'error: '")
    elif expect not in lines[0]:
        out.append(f"the error does not name '{expect}'")
    return out


def params():
    for c in CASES:
        marks = [pytest.mark.xfail(strict=True, reason=c.bug)] if c.bug else []
        yield pytest.param(c, id=c.id, marks=marks)


def test_corpus_is_large_enough():
    assert len(CASES) >= 100
    assert len({c.id for c in CASES}) == len(CASES), "duplicate case ids"


@pytest.mark.parametrize("c", params())
def test_bad_input(c, base_sequence, big_png, tmp_path):
    base, frames = base_sequence
    ok = False
    try:
        ctx = Ctx(base, tmp_path, frames, big_png)
        extra, expect = c.prepare(ctx)
        extra = [str(a) for a in extra]
        cmd = [BIN, "run", "--sequence", str(ctx.sequence), "--quiet", "--no-loop-closing",
               "--max-frames", str(ctx.max_frames)]
        if "--out" not in extra:
            cmd += ["--out", str(tmp_path / "out")]
        cmd += extra
        env = dict(os.environ)
        # what the asan test preset sets: any report is fatal
        env.setdefault("ASAN_OPTIONS", "detect_leaks=1:abort_on_error=1")
        env.setdefault("UBSAN_OPTIONS", "print_stacktrace=1:halt_on_error=1")
        try:
            r = subprocess.run(cmd, capture_output=True, text=True, errors="replace", timeout=TIMEOUT_S, env=env)
        except subprocess.TimeoutExpired:
            pytest.fail(f"hung for {TIMEOUT_S} s: {' '.join(cmd)}")
        problems = problems_with(r, expect)
        assert not problems, (f"{'; '.join(problems)}\n$ {' '.join(cmd)}\nexit {r.returncode}\n"
                              f"--- stderr ---\n{r.stderr[-4000:]}\n--- stdout ---\n{r.stdout[-2000:]}")
        ok = True
    finally:
        RESULTS[c.id] = (ok, c.bug)
