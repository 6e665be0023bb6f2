"""Export FNet to ONNX for the C++ side (OpenCV DNN 4.6, cv2.dnn.readNetFromONNX).

  /usr/bin/python3 -m training.fnet.export --ckpt best.pt --out fnet.onnx [--config fnet-lite]
                                           [--input-size 320x240] [--opset 11]

The graph has a FIXED input size (W x H, both even) and batch 1: sizes are baked as constants so
OpenCV 4.6 needs no shape inference. Input "image": 1x3xHxW float32 RGB in [0, 1]; mean/std
normalisation is inside the graph. Output "logits": 1x21xHxW, or 1x21x(H/2)x(W/2) for configs with
final_up "none" (fnet-lite; the consumer upsamples) - argmax over dim 1 = VOC class.
A model card <out>.json next to the .onnx records all of that (and the OpenCV check).
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import warnings
from typing import Optional, Tuple

import numpy as np
import torch

from .model import MEAN, STD, VOC_CLASSES, FNet, build_model, config_from_dict, count_params, deploy_copy

DEFAULT_OPSET = 11  # OpenCV 4.6's importer targets opsets <= 13; 11 is its best-tested one


def parse_size(text: str) -> Tuple[int, int]:
    """'320x240' -> (W, H)."""
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"size must look like 320x240, got '{text}'")
    if w <= 0 or h <= 0 or w % 2 or h % 2:
        raise argparse.ArgumentTypeError(f"size must be positive and even, got '{text}'")
    return w, h


def load_checkpoint(path: str, config: Optional[str] = None, map_location="cpu") -> Tuple[FNet, dict]:
    """Rebuilds the model from the config stored in the checkpoint (train.py writes it)."""
    ckpt = torch.load(path, map_location=map_location)
    state = ckpt.get("model", ckpt)
    if "config" in ckpt:
        cfg = config_from_dict(ckpt["config"])
        if config is not None and config != cfg.name:
            raise SystemExit(f"--config {config} does not match the checkpoint's config {cfg.name}")
        model = FNet(cfg)
    else:
        model = build_model(config or "fnet")
    model.load_state_dict(state)
    return model, ckpt


def inline_initializer_identities(path: str) -> int:
    """torch 1.13 always de-duplicates equal initializers (e.g. the zero biases of freshly folded BNs)
    and re-links them through Identity nodes, which OpenCV 4.6's importer rejects ("Identity ...
    inputs.size()"). Replace each such Identity by a copy of the initializer. Needs python3-onnx."""
    import onnx
    from onnx import numpy_helper

    m = onnx.load(path)
    inits = {t.name: t for t in m.graph.initializer}
    keep, n = [], 0
    for node in m.graph.node:
        if node.op_type == "Identity" and node.input[0] in inits:
            arr = numpy_helper.to_array(inits[node.input[0]])
            m.graph.initializer.append(numpy_helper.from_array(arr.copy(), node.output[0]))
            n += 1
        else:
            keep.append(node)
    if n:
        del m.graph.node[:]
        m.graph.node.extend(keep)
        onnx.save(m, path)
    return n


def export_onnx(model: FNet, out: str, size: Tuple[int, int] = (320, 240), opset: int = DEFAULT_OPSET,
                verify: bool = True, extra_card: Optional[dict] = None) -> dict:
    params = count_params(model)
    model = deploy_copy(model.cpu()).eval()  # stride-1 deconvolutions as the equivalent Conv
    w, h = size
    x = torch.rand(1, 3, h, w, generator=torch.Generator().manual_seed(0))
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    with torch.no_grad():
        torch.onnx.export(model, x, out, opset_version=opset, input_names=["image"], output_names=["logits"],
                          do_constant_folding=True)
        ref = model(x).numpy()
    try:
        inline_initializer_identities(out)
    except ImportError:
        print("warning: python3-onnx missing; Identity nodes left in the graph (OpenCV 4.6 may reject it)",
              file=sys.stderr)
    card = {
        "model": model.cfg.name,
        "config": model.cfg.to_dict(),
        "params": params,
        "onnx": os.path.basename(out),
        "opset": opset,
        "input": {"name": "image", "shape": [1, 3, h, w], "layout": "NCHW", "dtype": "float32",
                  "color_order": "RGB", "range": [0.0, 1.0],
                  "preprocess": "cv2.dnn.blobFromImage(bgr, 1/255.0, (W, H), Scalar(), swapRB=true, crop=false)",
                  "normalization_in_graph": {"mean": list(MEAN), "std": list(STD),
                                             "formula": "(x - mean) / std per RGB channel"}},
        "output": {"name": "logits", "shape": list(ref.shape),
                   "meaning": "per-pixel class logits; softmax/argmax over dim 1" +
                              ("" if tuple(ref.shape[-2:]) == (h, w) else
                               "; half the input resolution: resize bilinearly to the input size first"),
                   "classes": list(VOC_CLASSES),
                   "ignore_label": 255},
        "unpooling": "argmax-mask form of SegNet max-unpooling (training/fnet/unpool.py)",
        "torch": torch.__version__,
    }
    if verify:
        import cv2
        net = cv2.dnn.readNetFromONNX(out)
        net.setInput(x.numpy())
        got = net.forward()
        card["opencv"] = {"version": cv2.__version__, "max_abs_diff_vs_torch": float(np.abs(got - ref).max())}
    if extra_card:
        card.update(extra_card)
    with open(os.path.splitext(out)[0] + ".json", "w") as f:
        json.dump(card, f, indent=2)
    return card


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ckpt", help="checkpoint from train.py (omit for random weights, e.g. benchmarks)")
    ap.add_argument("--out", required=True, help="output .onnx path (model card written as .json beside it)")
    ap.add_argument("--config", choices=["fnet", "fnet-lite"], help="must match the checkpoint if given")
    ap.add_argument("--input-size", type=parse_size, default=(320, 240), help="WxH, even (default 320x240)")
    ap.add_argument("--opset", type=int, default=DEFAULT_OPSET)
    ap.add_argument("--no-verify", action="store_true", help="skip the cv2.dnn load-and-compare check")
    a = ap.parse_args(argv)
    torch.set_num_threads(max(1, min(2, os.cpu_count() or 1)))
    warnings.filterwarnings("ignore", category=torch.jit.TracerWarning)  # sizes baked on purpose
    warnings.filterwarnings("ignore", message=".*shape inference.*")
    if a.ckpt:
        model, ckpt = load_checkpoint(a.ckpt, a.config)
        extra = {"checkpoint": os.path.abspath(a.ckpt), "epoch": ckpt.get("epoch")}
    else:
        model, extra = build_model(a.config or "fnet"), {"checkpoint": None}
    card = export_onnx(model, a.out, a.input_size, a.opset, verify=not a.no_verify, extra_card=extra)
    msg = f"wrote {a.out} ({card['params']} params, input 1x3x{a.input_size[1]}x{a.input_size[0]} RGB [0,1])"
    if "opencv" in card:
        msg += f"; cv2.dnn {card['opencv']['version']} max|diff| = {card['opencv']['max_abs_diff_vs_torch']:.2e}"
    print(msg)
    return 0


if __name__ == "__main__":
    sys.exit(main())
