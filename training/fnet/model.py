"""FNet (LRD-SLAM paper section 2.6): Ghost-ResNet-50 encoder + SegNet/UNet decoder.

Encoder: ResNet-50 layout - stem (7x7/2 conv-BN-ReLU, 3x3/2 max-pool) and four stages of
bottleneck blocks [3, 4, 6, 3] (conv block with projection shortcut + identity blocks) - with
every convolution a GhostModule (ghost.py, GhostNet Eqs. 2-3; defaults s=2, d=3).

Decoder, one step per encoder scale H/16 -> H/8 -> H/4 -> H/2, then H/2 -> H:
  1. SegNet max-unpooling of the coarser decoder map with pooling indices saved in the encoder,
  2. UNet concatenation with the encoder feature map of the same resolution,
  3. trainable deconvolution (ConvTranspose 3x3, BN, ReLU) that densifies the sparse unpooled map.
A final ConvTranspose 4x4/2 reaches full resolution; a 1x1 classifier gives 21 VOC logits
(softmax lives in the loss / at inference; the ONNX graph outputs logits). fnet-lite instead
classifies at H/2 and leaves the last x2 to its consumer (final_up "none"): the training loss
upsamples the logits bilinearly, the C++ backend upsamples its per-pixel decision margin.

Where the indices come from (the paper leaves it open): ResNet-50 has one max-pool (the stem's
3x3/2, overlapping windows) and downsamples the other stages with stride-2 convolutions, so
SegNet's "reuse the encoder's pooling indices" cannot be taken literally at 4 of 5 scales. At every
scale k we save, in the encoder, the 2x2/2 argmax positions of the skip feature map l_k (the encoder
map e_k after a Ghost 1x1 lateral projection to the decoder width, which also keeps the decoder
small) - i.e. where inside each 2x2 cell the encoder response peaked. The decoder unpools into exactly
those positions and then concatenates l_k itself (UNet). Unpooling uses the exportable argmax-mask
form (unpool.py), bit-identical to max_pool2d indices + max_unpool2d.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass, replace
from typing import Dict, List, Tuple

import torch
import torch.nn.functional as F
from torch import nn

from .ghost import GhostBottleneck, GhostModule
from .unpool import Unpool

# Normalisation is part of the graph: the model takes RGB in [0, 1] (cv2.dnn.blobFromImage(bgr,
# 1/255, size, swapRB=True)); ImageNet statistics as usual for ResNet encoders.
MEAN = (0.485, 0.456, 0.406)
STD = (0.229, 0.224, 0.225)

VOC_CLASSES = ("background", "aeroplane", "bicycle", "bird", "boat", "bottle", "bus", "car", "cat",
               "chair", "cow", "diningtable", "dog", "horse", "motorbike", "person", "pottedplant",
               "sheep", "sofa", "train", "tvmonitor")


@dataclass(frozen=True)
class FNetConfig:
    name: str = "fnet"
    stem: int = 64                              # stem conv output channels
    stem_k: int = 7                             # stem kernel (ResNet-50: 7x7/2)
    widths: Tuple[int, ...] = (64, 128, 256, 512)  # bottleneck widths per stage (output = x expansion)
    blocks: Tuple[int, ...] = (3, 4, 6, 3)     # ResNet-50
    expansion: int = 4
    dec: Tuple[int, ...] = (32, 64, 128, 128)  # decoder widths at H/2, H/4, H/8, H/16
    head: int = 32                              # width of the full-resolution deconvolution
    s: int = 2                                  # Ghost ratio (paper Table 3: 2..5)
    d: int = 3                                  # cheap depthwise kernel
    num_classes: int = 21
    unpool: str = "mask"                        # unpool.py: "mask" (fast) or "first" (exact on ties)
    final_up: str = "deconv"                    # H/2 -> H: "deconv" (4x4/2, trainable), "bilinear" (fixed
                                                # resize of the logits) or "none" (H/2 logits out)
    lateral: str = "ghost"                      # decoder's 1x1 projections of the encoder maps: "ghost"
                                                # (Ghost module) or "conv" (plain conv-BN-ReLU)

    def to_dict(self) -> Dict:
        return asdict(self)


CONFIGS: Dict[str, FNetConfig] = {
    # The paper's network; decoder widths chosen so that s=2 gives ~12.2 M parameters (Table 3).
    "fnet": FNetConfig(),
    # Same design, narrower and one block per stage: real time on 2 CPU cores (training/bench_fnet.py).
    # From a cv2.dnn 4.6 sweep at 320x240 (2 threads, interleaved with the ORB yardstick): the H/2
    # layers dominate. No in-graph x2 of the logits (a 21-channel Resize at full size was 0.7 ms, and
    # the C++ argmax 4x the pixels; cv2.dnn's stride-2 Deconvolution alone costs > 10 ms): logits come
    # out at H/2. A 3x3 stem with 8 intrinsic maps instead of 7x7 with 4: 6.3 -> 4.8 ms together.
    # At run-time sizes (160x120 for the shipped model) it is bound by per-layer overhead: plain
    # 1x1 conv laterals instead of Ghost ones drop 10 of its 147 layers (at 192x144, 2.55 -> 2.28 ms).
    "fnet-lite": FNetConfig(name="fnet-lite", stem=16, stem_k=3, widths=(8, 16, 32, 64), blocks=(1, 1, 1, 1),
                            dec=(4, 12, 16, 32), head=8, final_up="none", lateral="conv"),
}


def get_config(name: str, **overrides) -> FNetConfig:
    if name not in CONFIGS:
        raise ValueError(f"unknown FNet config '{name}' (known: {', '.join(CONFIGS)})")
    cfg = CONFIGS[name]
    overrides = {k: (tuple(v) if isinstance(v, list) else v) for k, v in overrides.items() if v is not None}
    return replace(cfg, **overrides) if overrides else cfg


def config_from_dict(d: Dict) -> FNetConfig:
    return FNetConfig(**{k: (tuple(v) if isinstance(v, list) else v) for k, v in d.items()})


class GhostResNetEncoder(nn.Module):
    def __init__(self, cfg: FNetConfig):
        super().__init__()
        s, d = cfg.s, cfg.d
        self.stem = GhostModule(3, cfg.stem, cfg.stem_k, 2, s, d, relu=True)  # conv-BN-ReLU, H/2
        self.pool = nn.MaxPool2d(3, 2, 1)                             # H/4
        stages, cin = [], cfg.stem
        for i, (w, n) in enumerate(zip(cfg.widths, cfg.blocks)):
            stride = 1 if i == 0 else 2
            blocks = [GhostBottleneck(cin, w, cfg.expansion, stride, projection=True, s=s, d=d)]
            cin = w * cfg.expansion
            blocks += [GhostBottleneck(cin, w, cfg.expansion, 1, False, s, d) for _ in range(n - 1)]
            stages.append(nn.Sequential(*blocks))
        self.stages = nn.ModuleList(stages)
        self.channels = [cfg.stem] + [w * cfg.expansion for w in cfg.widths]  # e1..e5

    def forward(self, x: torch.Tensor) -> List[torch.Tensor]:
        e1 = self.stem(x)
        feats, y = [e1], self.pool(e1)
        for st in self.stages:
            y = st(y)
            feats.append(y)
        return feats  # resolutions H/2, H/4, H/8, H/16, H/32


class Deconv(nn.ConvTranspose2d):
    """Trainable deconvolution. A stride-1 transposed convolution IS a convolution with the kernel
    flipped and in/out swapped (padding k-1-p); computing it that way is bit-for-bit the same model
    but exports as Conv, which cv2.dnn 4.6 runs ~2x faster than its col2im Deconvolution."""

    def forward(self, x: torch.Tensor, output_size=None) -> torch.Tensor:
        if self.stride != (1, 1) or self.groups != 1 or self.dilation != (1, 1) or output_size is not None:
            return super().forward(x, output_size)
        k, p = self.kernel_size, self.padding
        w = self.weight.transpose(0, 1).flip(2, 3)
        return F.conv2d(x, w, self.bias, 1, (k[0] - 1 - p[0], k[1] - 1 - p[1]))

    def as_conv(self) -> nn.Conv2d:
        """The equivalent nn.Conv2d (export: keeps the flip out of the ONNX graph)."""
        k, p = self.kernel_size, self.padding
        conv = nn.Conv2d(self.in_channels, self.out_channels, k, 1, (k[0] - 1 - p[0], k[1] - 1 - p[1]),
                         bias=self.bias is not None)
        with torch.no_grad():
            conv.weight.copy_(self.weight.transpose(0, 1).flip(2, 3))
            if self.bias is not None:
                conv.bias.copy_(self.bias)
        return conv


def deploy_copy(model: nn.Module) -> nn.Module:
    """Copy of the model with stride-1 Deconv layers as Conv2d (same function, export-friendly)."""
    import copy

    m = copy.deepcopy(model)
    for parent in list(m.modules()):
        for name, child in parent.named_children():
            if isinstance(child, Deconv) and child.stride == (1, 1) and child.groups == 1 \
                    and child.dilation == (1, 1):
                setattr(parent, name, child.as_conv())
    return m


def deconv_bn_relu(cin: int, cout: int, k: int, stride: int) -> nn.Sequential:
    pad = (k - stride) // 2  # 3x3/1 keeps the size, 4x4/2 exactly doubles it
    return nn.Sequential(Deconv(cin, cout, k, stride, pad, bias=False),
                         nn.BatchNorm2d(cout), nn.ReLU(inplace=True))


class FNetDecoder(nn.Module):
    def __init__(self, cfg: FNetConfig, enc_channels: List[int]):
        super().__init__()
        s, d, dec = cfg.s, cfg.d, cfg.dec
        # Lateral 1x1 projections of e1..e4: the skip maps whose argmax positions are the indices.
        if cfg.lateral not in ("ghost", "conv"):
            raise ValueError(f"lateral must be 'ghost' or 'conv', got '{cfg.lateral}'")

        def projection(cin: int, cout: int) -> nn.Module:
            if cfg.lateral == "ghost":
                return GhostModule(cin, cout, 1, 1, s, d, relu=True)
            return nn.Sequential(nn.Conv2d(cin, cout, 1, bias=False), nn.BatchNorm2d(cout), nn.ReLU(inplace=True))

        self.lateral = nn.ModuleList(projection(c, w) for c, w in zip(enc_channels[:4], dec))
        self.center = projection(enc_channels[4], dec[3])  # e5 -> H/32 map
        outs = [cfg.head] + list(dec[:3])  # step k produces the width that step k-1 unpools
        self.densify = nn.ModuleList(deconv_bn_relu(2 * w, o, 3, 1) for w, o in zip(dec, outs))
        if cfg.final_up == "deconv":
            self.up = deconv_bn_relu(cfg.head, cfg.head, 4, 2)  # H/2 -> H, then classify
        elif cfg.final_up in ("bilinear", "none"):
            self.up = None                                      # classify at H/2 (then resize or not)
        else:
            raise ValueError(f"final_up must be 'deconv', 'bilinear' or 'none', got '{cfg.final_up}'")
        self.final_up = cfg.final_up
        self.classifier = nn.Conv2d(cfg.head, cfg.num_classes, 1)
        self.unpool = Unpool(cfg.unpool)

    def forward(self, feats: List[torch.Tensor]) -> torch.Tensor:
        y = self.center(feats[4])
        for k in (3, 2, 1, 0):
            skip = self.lateral[k](feats[k])
            idx = self.unpool.indices(skip)           # pooling indices "saved in the encoder"
            y = self.unpool(y, idx)                   # SegNet unpooling (sparse)
            y = self.densify[k](torch.cat([y, skip], 1))  # UNet concat + trainable deconvolution
        if self.up is not None:
            return self.classifier(self.up(y))
        if self.final_up == "none":
            return self.classifier(y)  # H/2 logits: upsample_logits() / the consumer does the x2
        return F.interpolate(self.classifier(y), scale_factor=2.0, mode="bilinear", align_corners=False)


class FNet(nn.Module):
    def __init__(self, cfg: FNetConfig = FNetConfig()):
        super().__init__()
        self.cfg = cfg
        self.register_buffer("mean", torch.tensor(MEAN).view(1, 3, 1, 1))
        self.register_buffer("std", torch.tensor(STD).view(1, 3, 1, 1))
        self.encoder = GhostResNetEncoder(cfg)
        self.decoder = FNetDecoder(cfg, self.encoder.channels)
        for m in self.modules():
            if isinstance(m, (nn.Conv2d, nn.ConvTranspose2d)):
                nn.init.kaiming_normal_(m.weight, mode="fan_out", nonlinearity="relu")
                if m.bias is not None:
                    nn.init.zeros_(m.bias)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        """x: N x 3 x H x W RGB in [0, 1] (H, W even) -> N x 21 x H x W logits (H/2 x W/2 when
        cfg.final_up is "none"; upsample_logits() brings them to the label size)."""
        return self.decoder(self.encoder((x - self.mean) / self.std))

    def set_encoder_frozen(self, frozen: bool) -> None:
        """Paper Table 1 recipe: encoder frozen for the first epochs (weights and BN statistics)."""
        for p in self.encoder.parameters():
            p.requires_grad_(not frozen)
        self._encoder_frozen = frozen
        if frozen:
            self.encoder.eval()

    def train(self, mode: bool = True):
        super().train(mode)
        if mode and getattr(self, "_encoder_frozen", False):
            self.encoder.eval()  # keep frozen BN running statistics untouched
        return self


def build_model(config: str | FNetConfig = "fnet", **overrides) -> FNet:
    cfg = get_config(config, **overrides) if isinstance(config, str) else config
    return FNet(cfg)


def upsample_logits(logits: torch.Tensor, size) -> torch.Tensor:
    """Logits at the label size (bilinear, half-pixel centres like cv::resize): a no-op for configs
    that already output full resolution."""
    if tuple(logits.shape[-2:]) == tuple(size):
        return logits
    return F.interpolate(logits, size=tuple(size), mode="bilinear", align_corners=False)


def count_params(model: nn.Module) -> int:
    return sum(p.numel() for p in model.parameters())
