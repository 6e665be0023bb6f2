"""Parameter count of FNet for Ghost ratios s = 2..5 beside the paper's Table 3.

  /usr/bin/python3 -m training.fnet.params_table [--config fnet]

Prints a Markdown table. Only builds the models (no forward pass), so it takes a few seconds.
"""
from __future__ import annotations

import argparse
import sys

import torch

from .model import build_model, count_params

PAPER_TABLE3 = {2: 12.2e6, 3: 10.8e6, 4: 10.1e6, 5: 9.7e6}  # LRD-SLAM Table 3, FNet params vs s


def rows(config: str = "fnet"):
    out = []
    for s, paper in PAPER_TABLE3.items():
        m = build_model(config, s=s)
        total, enc = count_params(m), count_params(m.encoder)
        out.append((s, total, enc, total - enc, paper))
    return out


def table(config: str = "fnet") -> str:
    lines = [f"| s | ours ({config}) | encoder | decoder | paper (Table 3) | ours / paper |",
             "|---:|---:|---:|---:|---:|---:|"]
    for s, total, enc, dec, paper in rows(config):
        lines.append(f"| {s} | {total / 1e6:.2f} M | {enc / 1e6:.2f} M | {dec / 1e6:.2f} M | "
                     f"{paper / 1e6:.1f} M | {total / paper:.3f} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--config", default="fnet", choices=["fnet", "fnet-lite"])
    a = ap.parse_args(argv)
    torch.set_num_threads(1)
    print(table(a.config))
    return 0


if __name__ == "__main__":
    sys.exit(main())
