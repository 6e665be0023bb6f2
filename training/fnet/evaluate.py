"""Evaluate an FNet checkpoint on the VOC val split (LRD-SLAM paper Table 2 layout).

  /usr/bin/python3 -m training.fnet.evaluate --voc DIR --ckpt FILE [--split val] [--input-size 320x240]
      [--device cpu|cuda] [--markdown OUT.md]

Per class: pixel accuracy PA_c = TP_c / (pixels of class c) and IoU_c = TP_c / (TP_c + FP_c + FN_c),
from one confusion matrix over all val pixels (255 ignored); MPA and mIoU are their means over
classes present in the ground truth. Also prints ms per frame (forward only, batch 1) and params.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

import numpy as np
import torch

from .export import load_checkpoint, parse_size
from .model import VOC_CLASSES, count_params, upsample_logits
from .voc import IGNORE, VOCSegmentation, read_ids, split_ids


def confusion(pred: np.ndarray, gt: np.ndarray, n: int) -> np.ndarray:
    keep = gt != IGNORE
    return np.bincount(n * gt[keep].astype(np.int64) + pred[keep], minlength=n * n).reshape(n, n)


def metrics(conf: np.ndarray):
    tp = np.diag(conf).astype(np.float64)
    gt, pr = conf.sum(1).astype(np.float64), conf.sum(0).astype(np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        pa = tp / gt
        iou = tp / (gt + pr - tp)
    present = gt > 0
    return pa, iou, float(np.nanmean(pa[present])) if present.any() else float("nan"), \
        float(np.nanmean(iou[present])) if present.any() else float("nan")


def markdown(pa, iou, mpa, miou, classes, ms, params, name) -> str:
    f = lambda v: "-" if not np.isfinite(v) else f"{100 * v:.1f}"
    lines = [f"FNet `{name}`: {params / 1e6:.2f} M parameters, {ms:.1f} ms/frame", "",
             "| Class | PA (%) | IoU (%) |", "|---|---:|---:|"]
    lines += [f"| {c} | {f(a)} | {f(u)} |" for c, a, u in zip(classes, pa, iou)]
    lines += [f"| **MPA / mIoU** | **{f(mpa)}** | **{f(miou)}** |"]
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--voc", required=True)
    ap.add_argument("--ckpt", required=True)
    ap.add_argument("--split", default="val", help="ImageSets/Segmentation/<split>.txt (val: held-out "
                                                   "10 %% of train when val.txt is missing)")
    ap.add_argument("--input-size", type=parse_size, default=(320, 240))
    ap.add_argument("--device", default="cpu", choices=["cpu", "cuda"])
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seed", type=int, default=0, help="must match training's --seed for the held-out split")
    ap.add_argument("--markdown", help="also write the table to this file")
    a = ap.parse_args(argv)
    torch.set_num_threads(max(1, a.threads))
    model, _ = load_checkpoint(a.ckpt)
    device = torch.device(a.device)
    model.to(device).eval()
    sets = os.path.join(a.voc, "ImageSets", "Segmentation")
    if a.split == "val" and not os.path.exists(os.path.join(sets, "val.txt")):
        ids = split_ids(a.voc, seed=a.seed)[1]
    else:
        ids = read_ids(os.path.join(sets, a.split + ".txt"))
    ds = VOCSegmentation(a.voc, ids, a.input_size)
    n = model.cfg.num_classes
    conf, times = np.zeros((n, n), np.int64), []
    with torch.no_grad():
        for i in range(len(ds)):
            x, y = ds[i]
            xt = torch.from_numpy(x)[None].to(device)
            if device.type == "cuda":
                torch.cuda.synchronize()
            t0 = time.perf_counter()
            logits = model(xt)
            if device.type == "cuda":
                torch.cuda.synchronize()
            times.append((time.perf_counter() - t0) * 1e3)
            logits = upsample_logits(logits, y.shape[-2:])
            conf += confusion(logits.argmax(1)[0].cpu().numpy(), y, n)
    pa, iou, mpa, miou = metrics(conf)
    ms = statistics.median(times) if times else float("nan")
    classes = VOC_CLASSES if n == len(VOC_CLASSES) else [str(i) for i in range(n)]
    table = markdown(pa, iou, mpa, miou, classes, ms, count_params(model), model.cfg.name)
    print(f"{len(ds)} images, input {a.input_size[0]}x{a.input_size[1]}\n")
    print(table)
    if a.markdown:
        with open(a.markdown, "w") as f:
            f.write(table + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
