"""What every case of the bad-input corpus shares: the case registry, file and PNG corruptions,
and the per-case context (a private copy of the valid sequence)."""
import os
import shutil
import struct
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Optional

import cv2
import numpy as np

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


