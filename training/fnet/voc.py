"""Pascal VOC segmentation reader + augmentation (training data for FNet, paper section 2.6).

Layout (VOC2012, SBD-augmented "SegmentationClassAug", or `lrdslam synth --export-voc`):
  DIR/JPEGImages/<id>.jpg
  DIR/SegmentationClass/<id>.png  or  DIR/SegmentationClassAug/<id>.png   (class index per pixel,
        0..20, 255 = ignore/boundary; VOC stores them as palette PNGs)
  DIR/ImageSets/Segmentation/{train,val}.txt  (one id per line)
Labels are read as palette INDICES: cv2.imread expands palettes to BGR colours (checked: it does,
even with IMREAD_UNCHANGED), so PIL (python3-pil) is used; without PIL, colour PNGs are mapped back
through the VOC colour map.
"""
from __future__ import annotations

import os
import random
from typing import List, Optional, Sequence, Tuple

import cv2
import numpy as np

IGNORE = 255


def voc_colormap(n: int = 256) -> np.ndarray:
    """The standard VOC palette (bit-interleaved), n x 3 RGB uint8; index 255 = (224, 224, 192)."""
    cmap = np.zeros((n, 3), np.uint8)
    for i in range(n):
        r = g = b = 0
        c = i
        for j in range(8):
            r |= ((c >> 0) & 1) << (7 - j)
            g |= ((c >> 1) & 1) << (7 - j)
            b |= ((c >> 2) & 1) << (7 - j)
            c >>= 3
        cmap[i] = (r, g, b)
    return cmap


def write_label_png(path: str, label: np.ndarray) -> None:
    """Writes a VOC-style palette PNG (needs PIL) - used by tests and synthetic exports."""
    from PIL import Image

    im = Image.fromarray(label.astype(np.uint8), mode="P")
    im.putpalette(voc_colormap().reshape(-1).tolist())
    im.save(path)


def read_label(path: str) -> np.ndarray:
    """H x W uint8 class indices (255 = ignore)."""
    try:
        from PIL import Image

        with Image.open(path) as im:
            if im.mode in ("P", "L"):
                return np.array(im, dtype=np.uint8)
            rgb = np.array(im.convert("RGB"))
    except ImportError:
        raw = cv2.imread(path, cv2.IMREAD_UNCHANGED)
        if raw is None:
            raise FileNotFoundError(path)
        if raw.ndim == 2:
            return raw.astype(np.uint8)
        rgb = cv2.cvtColor(raw[:, :, :3], cv2.COLOR_BGR2RGB)
    # Colour label image: invert the VOC colour map; unknown colours become IGNORE.
    cmap = voc_colormap().astype(np.int32)
    key = (cmap[:, 0] << 16) | (cmap[:, 1] << 8) | cmap[:, 2]
    lut = {int(k): i for i, k in enumerate(key) if i < 21 or i == IGNORE}
    flat = (rgb[..., 0].astype(np.int32) << 16) | (rgb[..., 1].astype(np.int32) << 8) | rgb[..., 2]
    out = np.full(flat.shape, IGNORE, np.uint8)
    for k, i in lut.items():
        out[flat == k] = i
    return out


def read_ids(path: str) -> List[str]:
    with open(path) as f:
        return [ln.strip().split()[0] for ln in f if ln.strip()]


def label_dir(root: str) -> str:
    for name in ("SegmentationClassAug", "SegmentationClass"):
        if os.path.isdir(os.path.join(root, name)):
            return os.path.join(root, name)
    raise FileNotFoundError(f"{root}: neither SegmentationClassAug/ nor SegmentationClass/ found")


def split_ids(root: str, val_fraction: float = 0.1, seed: int = 0) -> Tuple[List[str], List[str]]:
    """train.txt and val.txt; without val.txt, a seeded 10 % of train is held out (paper recipe)."""
    sets = os.path.join(root, "ImageSets", "Segmentation")
    train = read_ids(os.path.join(sets, "train.txt"))
    val_path = os.path.join(sets, "val.txt")
    if os.path.exists(val_path):
        return train, read_ids(val_path)
    ids = sorted(train)
    random.Random(seed).shuffle(ids)
    n_val = max(1, int(round(len(ids) * val_fraction))) if len(ids) > 1 else 0
    return sorted(ids[n_val:]), sorted(ids[:n_val])


class Augment:
    """Random scale, pad+crop to the network input, horizontal flip, colour jitter.

    Deterministic: every call takes its own np.random.Generator (train.py seeds it from
    (seed, epoch, index)), so results do not depend on worker scheduling."""

    def __init__(self, size: Tuple[int, int], scale: Tuple[float, float] = (0.5, 2.0), flip: bool = True,
                 jitter: float = 0.3, hue: float = 0.05):
        self.w, self.h = size
        self.scale, self.flip, self.jitter, self.hue = scale, flip, jitter, hue

    def __call__(self, img: np.ndarray, lab: np.ndarray, rng: np.random.Generator):
        s = rng.uniform(*self.scale)
        nh, nw = max(1, int(round(img.shape[0] * s))), max(1, int(round(img.shape[1] * s)))
        img = cv2.resize(img, (nw, nh), interpolation=cv2.INTER_LINEAR)
        lab = cv2.resize(lab, (nw, nh), interpolation=cv2.INTER_NEAREST)  # never blend class ids
        ph, pw = max(0, self.h - nh), max(0, self.w - nw)
        if ph or pw:  # pad image with grey, label with ignore so padding never counts as background
            img = cv2.copyMakeBorder(img, 0, ph, 0, pw, cv2.BORDER_CONSTANT, value=(124, 116, 104))
            lab = cv2.copyMakeBorder(lab, 0, ph, 0, pw, cv2.BORDER_CONSTANT, value=IGNORE)
        y = int(rng.integers(0, img.shape[0] - self.h + 1))
        x = int(rng.integers(0, img.shape[1] - self.w + 1))
        img, lab = img[y:y + self.h, x:x + self.w], lab[y:y + self.h, x:x + self.w]
        if self.flip and rng.random() < 0.5:
            img, lab = img[:, ::-1], lab[:, ::-1]
        if self.jitter > 0:
            img = self.colour(img, rng)
        return np.ascontiguousarray(img), np.ascontiguousarray(lab)

    def colour(self, img: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        f = img.astype(np.float32)
        j = self.jitter
        f = f * rng.uniform(1 - j, 1 + j)                                   # brightness
        mean = f.mean()
        f = (f - mean) * rng.uniform(1 - j, 1 + j) + mean                   # contrast
        grey = f.mean(axis=2, keepdims=True)
        f = (f - grey) * rng.uniform(1 - j, 1 + j) + grey                   # saturation
        f = np.clip(f, 0, 255).astype(np.uint8)
        if self.hue > 0:                                                     # hue (OpenCV H in 0..179)
            hsv = cv2.cvtColor(f, cv2.COLOR_RGB2HSV)
            shift = int(round(rng.uniform(-self.hue, self.hue) * 180))
            hsv[..., 0] = ((hsv[..., 0].astype(np.int32) + shift) % 180).astype(np.uint8)
            f = cv2.cvtColor(hsv, cv2.COLOR_HSV2RGB)
        return f


class VOCSegmentation:
    """Map-style dataset: item -> (float32 3xHxW RGB in [0,1], int64 HxW labels)."""

    def __init__(self, root: str, ids: Sequence[str], size: Tuple[int, int], augment: Optional[Augment] = None,
                 seed: int = 0):
        self.root, self.ids, self.size, self.augment, self.seed = root, list(ids), size, augment, seed
        self.labels = label_dir(root)
        self.epoch = 0

    def __len__(self) -> int:
        return len(self.ids)

    def load(self, i: int) -> Tuple[np.ndarray, np.ndarray]:
        name = self.ids[i]
        bgr = cv2.imread(os.path.join(self.root, "JPEGImages", name + ".jpg"), cv2.IMREAD_COLOR)
        if bgr is None:
            raise FileNotFoundError(os.path.join(self.root, "JPEGImages", name + ".jpg"))
        lab = read_label(os.path.join(self.labels, name + ".png"))
        if lab.shape != bgr.shape[:2]:
            raise ValueError(f"{name}: image {bgr.shape[:2]} and label {lab.shape} sizes differ")
        return cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB), lab

    def __getitem__(self, i: int):
        img, lab = self.load(i)
        if self.augment is not None:
            rng = np.random.default_rng([self.seed, self.epoch, i])
            img, lab = self.augment(img, lab, rng)
        else:  # evaluation: plain resize to the network input (labels nearest)
            w, h = self.size
            img = cv2.resize(img, (w, h), interpolation=cv2.INTER_LINEAR)
            lab = cv2.resize(lab, (w, h), interpolation=cv2.INTER_NEAREST)
        x = img.transpose(2, 0, 1).astype(np.float32) / 255.0
        return x, lab.astype(np.int64)
