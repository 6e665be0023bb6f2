"""Ghost module (GhostNet, Han et al. 2020, Eqs. 2-3) - the convolution FNet uses everywhere
in its encoder (LRD-SLAM paper section 2.6).

An ordinary k x k convolution producing n maps is replaced by
  * a primary k x k convolution producing m = ceil(n / s) "intrinsic" maps  (GhostNet Eq. 2),
  * a cheap d x d depthwise convolution producing (s - 1) * m "ghost" maps from them
    (GhostNet Eq. 3: y_ij = Phi_ij(y'_i), j = 1..s-1), and
  * the identity Phi_{i,s}: the intrinsic maps are kept and concatenated with the ghosts.
The first n of the m * s maps are returned (only matters when s does not divide n).
"""
from __future__ import annotations

import math

import torch
from torch import nn


def ghost_param_count(cin: int, cout: int, k: int, s: int = 2, d: int = 3, bn: bool = True) -> int:
    """Closed-form parameter count of GhostModule (used by tests and params_table).

    primary conv: cin * m * k^2, cheap depthwise: (s-1) * m * d^2, BatchNorm: 2 per map (m * s maps).
    Compare cin * n * k^2 for the ordinary convolution: the ratio tends to 1/s (GhostNet Eq. 4)."""
    m = math.ceil(cout / s)
    n = cin * m * k * k + (s - 1) * m * d * d
    if bn:
        n += 2 * m + (2 * (s - 1) * m if s > 1 else 0)
    return n


class GhostModule(nn.Module):
    def __init__(self, cin: int, cout: int, k: int = 1, stride: int = 1, s: int = 2, d: int = 3,
                 relu: bool = True):
        super().__init__()
        if s < 1:
            raise ValueError("Ghost ratio s must be >= 1")
        self.cout = cout
        m = math.ceil(cout / s)
        act = [nn.ReLU(inplace=True)] if relu else []
        # Eq. 2: Y' = X * f' (bias-free; BN follows as in GhostNet).
        self.primary = nn.Sequential(nn.Conv2d(cin, m, k, stride, k // 2, bias=False), nn.BatchNorm2d(m), *act)
        # Eq. 3: every intrinsic map i spawns s-1 ghosts through its own d x d depthwise filter
        # (groups=m: output channels i*(s-1) .. i*(s-1)+s-2 are the ghosts of intrinsic map i).
        if s > 1:
            self.cheap = nn.Sequential(nn.Conv2d(m, m * (s - 1), d, 1, d // 2, groups=m, bias=False),
                                       nn.BatchNorm2d(m * (s - 1)), *act)
        else:
            self.cheap = None  # s = 1 degenerates to the ordinary convolution
        self.sliced = m * s != cout

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        y = self.primary(x)
        if self.cheap is None:
            return y
        out = torch.cat([y, self.cheap(y)], dim=1)  # identity maps first, then the ghosts
        return out[:, : self.cout] if self.sliced else out


class GhostBottleneck(nn.Module):
    """ResNet-50 bottleneck (1x1 reduce, 3x3, 1x1 expand x4) with every conv a GhostModule.

    projection=True is ResNet's "conv block" (1x1 projection shortcut, first block of a stage);
    False is the "identity block". The stride sits on the 3x3 (torchvision's ResNet v1.5)."""

    def __init__(self, cin: int, width: int, expansion: int = 4, stride: int = 1, projection: bool = False,
                 s: int = 2, d: int = 3):
        super().__init__()
        cout = width * expansion
        self.body = nn.Sequential(
            GhostModule(cin, width, 1, 1, s, d, relu=True),
            GhostModule(width, width, 3, stride, s, d, relu=True),
            GhostModule(width, cout, 1, 1, s, d, relu=False),  # no ReLU before the residual sum
        )
        if projection:
            self.shortcut = GhostModule(cin, cout, 1, stride, s, d, relu=False)
        else:
            if cin != cout or stride != 1:
                raise ValueError("identity block needs cin == cout and stride 1")
            self.shortcut = nn.Identity()
        self.relu = nn.ReLU(inplace=True)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return self.relu(self.body(x) + self.shortcut(x))
