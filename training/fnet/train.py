"""Train FNet on a Pascal-VOC-layout folder with the paper's recipe (LRD-SLAM Table 1).

  /usr/bin/python3 -m training.fnet.train --voc DIR --out DIR [--config fnet|fnet-lite] [--epochs 200]
      [--batch 4] [--lr 1e-3] [--freeze-epochs 70] [--resume CKPT] [--device cpu|cuda]
      [--input-size 320x240] [--seed 0]

Table 1: Adam, lr 1e-3, ReLU, batch 4, 200 epochs; the encoder is frozen for the first 70 epochs
and then unfrozen; ReduceLROnPlateau on the validation loss (patience 3). Without val.txt a seeded
10 % of train.txt is held out. Writes OUT/epoch_NNN.pt (last --keep kept), OUT/last.pt, OUT/best.pt
(lowest val loss), OUT/history.csv and OUT/loss.png (train/val loss vs epoch, like the paper's Fig. 7).
"""
from __future__ import annotations

import argparse
import csv
import glob
import os
import random
import sys
import time
from typing import Dict, List

import cv2
import numpy as np
import torch
from torch import nn

from .export import parse_size
from .model import FNet, build_model, config_from_dict, count_params, upsample_logits
from .voc import IGNORE, Augment, VOCSegmentation, split_ids


def seed_everything(seed: int) -> None:
    random.seed(seed)
    np.random.seed(seed)
    torch.manual_seed(seed)
    torch.use_deterministic_algorithms(True, warn_only=True)
    if torch.cuda.is_available():
        torch.backends.cudnn.benchmark = False
        torch.backends.cudnn.deterministic = True


def make_loader(ds: VOCSegmentation, batch: int, shuffle: bool, seed: int, epoch: int, workers: int):
    ds.epoch = epoch  # augmentation RNG is seeded per (seed, epoch, index)
    g = torch.Generator().manual_seed(seed * 100003 + epoch)
    return torch.utils.data.DataLoader(ds, batch_size=batch, shuffle=shuffle, generator=g, num_workers=workers,
                                       drop_last=False)


def run_epoch(model: FNet, loader, loss_fn, device, optimizer=None) -> float:
    """One pass; trains when an optimizer is given. Returns the pixel-mean loss."""
    training = optimizer is not None
    model.train(training)
    total, count = 0.0, 0
    with torch.set_grad_enabled(training):
        for x, y in loader:
            x, y = x.to(device), y.to(device)
            logits = upsample_logits(model(x), y.shape[-2:])
            loss = loss_fn(logits, y)  # softmax cross-entropy over the 21 classes, 255 ignored
            if training:
                optimizer.zero_grad(set_to_none=True)
                loss.backward()
                optimizer.step()
            n = int((y != IGNORE).sum())
            if n:
                total += float(loss) * n
                count += n
    return total / max(count, 1)


def plot_losses(history: List[Dict], path: str, freeze_epochs: int = 0) -> None:
    """Train/val loss vs epoch drawn with cv2 (matplotlib is not a dependency)."""
    W, H, L, R, T, B = 800, 500, 70, 20, 30, 50
    img = np.full((H, W, 3), 255, np.uint8)
    ep = [h["epoch"] for h in history]
    vals = [h[k] for h in history for k in ("train_loss", "val_loss") if np.isfinite(h[k])]
    if not ep or not vals:
        cv2.imwrite(path, img)
        return
    x0, x1 = min(ep), max(max(ep), min(ep) + 1)
    y0, y1 = 0.0, max(vals) * 1.05 + 1e-9
    px = lambda e: int(L + (e - x0) / (x1 - x0) * (W - L - R))
    py = lambda v: int(H - B - (v - y0) / (y1 - y0) * (H - T - B))
    cv2.rectangle(img, (L, T), (W - R, H - B), (0, 0, 0), 1)
    for i in range(6):
        v = y0 + (y1 - y0) * i / 5
        cv2.putText(img, f"{v:.3f}", (5, py(v) + 4), cv2.FONT_HERSHEY_SIMPLEX, 0.4, (0, 0, 0), 1, cv2.LINE_AA)
        e = x0 + (x1 - x0) * i / 5
        cv2.putText(img, f"{e:.0f}", (px(e) - 8, H - B + 18), cv2.FONT_HERSHEY_SIMPLEX, 0.4, (0, 0, 0), 1)
    if x0 < freeze_epochs < x1:  # unfreeze point
        cv2.line(img, (px(freeze_epochs), T), (px(freeze_epochs), H - B), (180, 180, 180), 1)
    for key, colour in (("train_loss", (200, 80, 0)), ("val_loss", (0, 0, 220))):
        pts = [(px(h["epoch"]), py(h[key])) for h in history if np.isfinite(h[key])]
        if len(pts) > 1:
            cv2.polylines(img, [np.array(pts, np.int32)], False, colour, 2, cv2.LINE_AA)
        for p in pts[-1:] if len(pts) == 1 else []:
            cv2.circle(img, p, 3, colour, -1)
    cv2.putText(img, "train loss", (W - 180, T + 20), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (200, 80, 0), 1, cv2.LINE_AA)
    cv2.putText(img, "val loss", (W - 180, T + 40), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (0, 0, 220), 1, cv2.LINE_AA)
    cv2.putText(img, "epoch", (W // 2 - 20, H - 12), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (0, 0, 0), 1, cv2.LINE_AA)
    cv2.imwrite(path, img)


def save(path: str, model, optimizer, scheduler, epoch, history, best, args) -> None:
    torch.save({"model": model.state_dict(), "config": model.cfg.to_dict(), "epoch": epoch,
                "optimizer": optimizer.state_dict(), "scheduler": scheduler.state_dict(),
                "history": history, "best_val": best, "args": vars(args),
                "torch_rng": torch.get_rng_state()}, path)


def init_from(model: FNet, path: str) -> None:
    """--init: the checkpoint's weights where they fit this model (all of them for the same config)."""
    ckpt = torch.load(path, map_location="cpu")
    state = ckpt.get("model", ckpt)
    own = model.state_dict()
    taken = {k: v for k, v in state.items() if k in own and own[k].shape == v.shape}
    if not taken:
        raise SystemExit(f"{path}: --init checkpoint has no tensor that fits FNet {model.cfg.name}")
    if ckpt.get("config") == model.cfg.to_dict() and len(taken) != len(own):
        raise SystemExit(f"{path}: --init checkpoint has the same configuration but not all its tensors")
    model.load_state_dict(taken, strict=False)
    fresh = sorted({k.rsplit(".", 1)[0] for k in own if k not in taken})
    print(f"init: {len(taken)} of {len(own)} tensors from {path}"
          + (f"; fresh: {', '.join(fresh)}" if fresh else ""), flush=True)


def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--voc", required=True, help="VOC-layout root (JPEGImages, SegmentationClass[Aug], ImageSets)")
    ap.add_argument("--out", required=True, help="output directory for checkpoints, history and loss.png")
    ap.add_argument("--config", default="fnet", choices=["fnet", "fnet-lite"])
    ap.add_argument("--ghost-s", type=int, default=None, help="override the Ghost ratio s (Table 3)")
    ap.add_argument("--lateral", choices=["ghost", "conv"], default=None,
                    help="override the decoder's 1x1 lateral projections (fnet: ghost, fnet-lite: conv)")
    ap.add_argument("--epochs", type=int, default=200)
    ap.add_argument("--batch", type=int, default=4)
    ap.add_argument("--lr", type=float, default=1e-3)
    ap.add_argument("--freeze-epochs", type=int, default=70, help="encoder frozen for these first epochs")
    ap.add_argument("--patience", type=int, default=3, help="ReduceLROnPlateau patience (val loss)")
    ap.add_argument("--lr-factor", type=float, default=0.5, help="ReduceLROnPlateau factor")
    ap.add_argument("--val-fraction", type=float, default=0.1, help="held out when there is no val.txt")
    ap.add_argument("--encoder-weights", help="state_dict/checkpoint to initialise the encoder from")
    ap.add_argument("--init", help="checkpoint whose model starts this run (fine-tuning, e.g. for another input "
                                   "size; optimizer and epochs start afresh). Another configuration: the tensors "
                                   "whose names and shapes match are taken, the rest start fresh (listed)")
    ap.add_argument("--resume", help="checkpoint to resume from (e.g. OUT/last.pt)")
    ap.add_argument("--device", default="cpu", choices=["cpu", "cuda"])
    ap.add_argument("--input-size", type=parse_size, default=(320, 240), help="WxH crop size")
    ap.add_argument("--scale-range", type=float, nargs=2, default=(0.5, 2.0), metavar=("MIN", "MAX"),
                    help="random image scale before the crop (0.5 2.0: VOC practice; for 640x480 frames "
                         "that the model sees resized to 320x240, about 0.45 1.0 matches inference)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--workers", type=int, default=0)
    ap.add_argument("--threads", type=int, default=1, help="torch CPU threads")
    ap.add_argument("--keep", type=int, default=3, help="how many epoch_NNN.pt to keep")
    ap.add_argument("--max-steps", type=int, default=0, help=argparse.SUPPRESS)  # smoke tests
    return ap.parse_args(argv)


def main(argv=None) -> int:
    args = parse_args(argv)
    torch.set_num_threads(max(1, args.threads))
    seed_everything(args.seed)
    if args.device == "cuda" and not torch.cuda.is_available():
        raise SystemExit("--device cuda: no CUDA device visible to torch")
    device = torch.device(args.device)
    os.makedirs(args.out, exist_ok=True)

    if sum(bool(v) for v in (args.init, args.encoder_weights, args.resume)) > 1:
        raise SystemExit("--init, --encoder-weights and --resume exclude each other")
    ckpt = torch.load(args.resume, map_location="cpu") if args.resume else None
    if ckpt is not None:
        model = FNet(config_from_dict(ckpt["config"]))
        model.load_state_dict(ckpt["model"])
    else:
        model = build_model(args.config, s=args.ghost_s, lateral=args.lateral)
        if args.init:
            init_from(model, args.init)
        elif args.encoder_weights:
            sd = torch.load(args.encoder_weights, map_location="cpu")
            sd = sd.get("model", sd)
            enc = {k[len("encoder."):]: v for k, v in sd.items() if k.startswith("encoder.")} or sd
            model.encoder.load_state_dict(enc)
    model.to(device)

    train_ids, val_ids = split_ids(args.voc, args.val_fraction, args.seed)
    if not train_ids:
        raise SystemExit(f"{args.voc}: no training images")
    train_ds = VOCSegmentation(args.voc, train_ids, args.input_size,
                               Augment(args.input_size, scale=tuple(args.scale_range)), args.seed)
    val_ds = VOCSegmentation(args.voc, val_ids, args.input_size, None, args.seed)
    loss_fn = nn.CrossEntropyLoss(ignore_index=IGNORE)
    optimizer = torch.optim.Adam(model.parameters(), lr=args.lr)  # frozen params get no grad: skipped
    scheduler = torch.optim.lr_scheduler.ReduceLROnPlateau(optimizer, "min", factor=args.lr_factor,
                                                           patience=args.patience)
    history, best, start = [], float("inf"), 1
    if ckpt is not None:
        optimizer.load_state_dict(ckpt["optimizer"])
        scheduler.load_state_dict(ckpt["scheduler"])
        history, best, start = ckpt["history"], ckpt["best_val"], ckpt["epoch"] + 1
        torch.set_rng_state(ckpt["torch_rng"])
    print(f"FNet {model.cfg.name} s={model.cfg.s}: {count_params(model)} params; {len(train_ids)} train / "
          f"{len(val_ids)} val images; epochs {start}..{args.epochs}", flush=True)

    for epoch in range(start, args.epochs + 1):
        model.set_encoder_frozen(epoch <= args.freeze_epochs)
        t0 = time.time()
        loader = make_loader(train_ds, args.batch, True, args.seed, epoch, args.workers)
        if args.max_steps:
            loader = [b for _, b in zip(range(args.max_steps), loader)]
        train_loss = run_epoch(model, loader, loss_fn, device, optimizer)
        val_loss = (run_epoch(model, make_loader(val_ds, args.batch, False, args.seed, epoch, args.workers),
                              loss_fn, device) if len(val_ds) else float("nan"))
        scheduler.step(val_loss if np.isfinite(val_loss) else train_loss)
        lr = optimizer.param_groups[0]["lr"]
        history.append({"epoch": epoch, "train_loss": train_loss, "val_loss": val_loss, "lr": lr,
                        "frozen": epoch <= args.freeze_epochs, "seconds": time.time() - t0})
        monitored = val_loss if np.isfinite(val_loss) else train_loss
        is_best = monitored < best
        best = min(best, monitored)
        path = os.path.join(args.out, f"epoch_{epoch:03d}.pt")
        save(path, model, optimizer, scheduler, epoch, history, best, args)
        save(os.path.join(args.out, "last.pt"), model, optimizer, scheduler, epoch, history, best, args)
        if is_best:
            save(os.path.join(args.out, "best.pt"), model, optimizer, scheduler, epoch, history, best, args)
        for old in sorted(glob.glob(os.path.join(args.out, "epoch_*.pt")))[:-max(1, args.keep)]:
            os.remove(old)
        with open(os.path.join(args.out, "history.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(history[0]))
            w.writeheader()
            w.writerows(history)
        plot_losses(history, os.path.join(args.out, "loss.png"), args.freeze_epochs)
        print(f"epoch {epoch:3d}  train {train_loss:.4f}  val {val_loss:.4f}  lr {lr:.2e}"
              f"{'  (encoder frozen)' if epoch <= args.freeze_epochs else ''}{'  *best' if is_best else ''}"
              f"  {time.time() - t0:.1f}s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
