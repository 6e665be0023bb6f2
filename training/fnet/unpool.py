"""SegNet-style max-unpooling that exports to ops OpenCV 4.6's ONNX importer supports.

Why not MaxPool(indices) + MaxUnpool: PyTorch 1.13 cannot export aten::max_unpool2d to ONNX at
all (UnsupportedOperatorError), and OpenCV 4.6 would also need the indices output of MaxPool.
Instead the "pooling indices" of a 2x2/2 max-pool of the encoder map x are carried as a 0/1 mask
at x's resolution, and unpooling is "nearest-upsample, then keep only the argmax positions":

  mode "mask" (FNet default, both configs):  M = [x == up(maxpool(x))],  out = up(y) * M
      Ops: MaxPool, Resize(nearest), Equal, Cast, Mul - about 1 ms at H/2 in cv2.dnn. Identical to
      max_unpool2d(y, indices) whenever each 2x2 window has a unique maximum; if several entries tie
      for the max (ReLU zeros, flat regions) the value goes to every tied position instead of the
      first one (for an all-zero window that is plain nearest upsampling).
  mode "first": bit-identical to PyTorch's indices including ties (first maximum in raster order):
      split x into its four phases a=x[0::2,0::2], b=x[0::2,1::2], c=x[1::2,0::2], e=x[1::2,1::2]
      (strided Slice), p = max(a,b,c,e), f_a=[a==p], f_b=[b==p](1-[a==p]), f_c=[c==p](1-[a==p])(1-[b==p]),
      f_e=[e==p](...)(...)(...); out = pixel_shuffle(stack(y*f_a, y*f_b, y*f_c, y*f_e)) (DepthToSpace).
      Also loads in cv2.dnn 4.6, but its strided slices and 6-D permute cost ~15x more.
Both run unchanged in training and in the exported graph (no train/deploy gap); tests/python/
test_fnet.py proves the equivalences against F.max_pool2d(return_indices=True) + F.max_unpool2d.
Odd sizes: pooling uses ceil_mode (a padded cell never wins), the result is cropped to x's size.
"""
from __future__ import annotations

from typing import List, Tuple

import torch
import torch.nn.functional as F

NEG = -3.4028234e38  # -FLT_MAX: a padded cell never beats a real one


def _even(x: torch.Tensor) -> Tuple[torch.Tensor, int, int]:
    # int() bakes sizes as constants in the exported graph (fixed-size model for OpenCV).
    h, w = int(x.shape[-2]), int(x.shape[-1])
    ph, pw = h % 2, w % 2
    if ph or pw:
        x = F.pad(x, (0, pw, 0, ph), value=NEG)
    return x, h, w


def argmax_masks(x: torch.Tensor) -> Tuple[List[torch.Tensor], Tuple[int, int]]:
    """Mode "first": the indices of a 2x2/2 max-pool of x as four one-hot phase masks (float 0/1)."""
    x, h, w = _even(x)
    a, b = x[:, :, 0::2, 0::2], x[:, :, 0::2, 1::2]
    c, e = x[:, :, 1::2, 0::2], x[:, :, 1::2, 1::2]
    p = torch.max(torch.max(a, b), torch.max(c, e))
    ma, mb, mc, me = [(t == p).to(x.dtype) for t in (a, b, c, e)]
    na = 1.0 - ma           # no max earlier than b
    nab = na * (1.0 - mb)   # no max earlier than c
    nabc = nab * (1.0 - mc)  # no max earlier than e
    return [ma, mb * na, mc * nab, me * nabc], (h, w)


def max_mask(x: torch.Tensor) -> torch.Tensor:
    """Mode "mask": 1 where x equals the max of its 2x2/2 window (all tied maxima), else 0."""
    h, w = int(x.shape[-2]), int(x.shape[-1])
    up = F.interpolate(F.max_pool2d(x, 2, 2, ceil_mode=True), scale_factor=2.0, mode="nearest")
    if up.shape[-2] != h or up.shape[-1] != w:
        up = up[:, :, :h, :w]
    return (x == up).to(x.dtype)


def unpool_mask(y: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
    """Mode "mask" unpooling: y (pooled resolution) nearest-upsampled, kept only where mask == 1."""
    h, w = int(mask.shape[-2]), int(mask.shape[-1])
    up = F.interpolate(y, scale_factor=2.0, mode="nearest")
    if up.shape[-2] != h or up.shape[-1] != w:
        up = up[:, :, :h, :w]
    return up * mask


def unpool_masks(y: torch.Tensor, masks: List[torch.Tensor], size: Tuple[int, int]) -> torch.Tensor:
    """Mode "first": max_unpool2d(y, indices) with indices from argmax_masks(); cropped to `size`."""
    n, c, hh, ww = (int(v) for v in y.shape)
    z = torch.stack([y * m for m in masks], dim=2).reshape(-1, c * 4, hh, ww)  # channel = c*4 + phase
    out = F.pixel_shuffle(z, 2)  # phase (i, j) -> pixel (2r+i, 2q+j): ONNX DepthToSpace(CRD)
    h, w = size
    if out.shape[-2] != h or out.shape[-1] != w:
        out = out[:, :, :h, :w]
    return out


class Unpool:
    """Saves the indices of skip map x (encoder side) and unpools y into them (decoder side)."""

    MODES = ("mask", "first")

    def __init__(self, mode: str = "mask"):
        if mode not in self.MODES:
            raise ValueError(f"unpool mode must be one of {self.MODES}, got '{mode}'")
        self.mode = mode

    def indices(self, x: torch.Tensor):
        return max_mask(x) if self.mode == "mask" else argmax_masks(x)

    def __call__(self, y: torch.Tensor, idx) -> torch.Tensor:
        return unpool_mask(y, idx) if self.mode == "mask" else unpool_masks(y, *idx)


# Reference implementation with real indices (PyTorch only; not exportable) - used by the tests.
def pool_indices(x: torch.Tensor):
    return F.max_pool2d(x, 2, 2, ceil_mode=True, return_indices=True)


def unpool_indices(y: torch.Tensor, idx: torch.Tensor, size: Tuple[int, int]) -> torch.Tensor:
    return F.max_unpool2d(y, idx, 2, 2, output_size=size)
