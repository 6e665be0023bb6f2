#!/usr/bin/python3
"""Profile of an lrd-slam run per thread and per stage (bench/results/profile.md).

    perf record -F 999 -o perf.data -- build/release/bin/lrdslam run --sequence SEQ --mode full --out OUT
    bench/perf_stages.py perf.data [--top 12]

Every background thread names itself (util::name_this_thread: lrd-mapping, lrd-segment, ...), so the
samples split by thread; tracking runs in the main thread (`lrdslam`). Its symbols are grouped into
the stages of FrameTiming (extraction, the dynamic-scene front end, tracking) plus what no stage owns
(memory allocation, the kernel), and each thread's top symbols are listed.
"""
import argparse
import re
import subprocess
import sys

# First match wins; a symbol line is "DSO SYMBOL".
STAGES = [
    ("descriptor distances (popcount)", r"popcount"),
    ("extraction (ORB: pyramid, FAST, orientation, descriptors)",
     r"lrd::features::|libopencv_(imgproc|features2d)|cv::(resize|GaussianBlur|FAST)"),
    ("dynamic front end (mask carry-over, geometry check, regions)", r"lrd::dynamic::|lrd::segmentation::"),
    ("tracking (matching, pose optimization, local map, keyframes)",
     r"lrd::(optim|match|tracking|data|map|place)::|ceres::|Eigen::"),
    ("memory allocation", r"\b(malloc|cfree|free|_int_free|_int_malloc|unlink_chunk|operator new|operator delete)"),
    ("kernel", r"\[k\]|kallsyms"),
]


def report(data, args):
    cmd = ["perf", "report", "-i", data, "--stdio", "--percentage", "relative"] + args
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"perf_stages.py: error: {data}: perf report failed: {out.stderr.strip().splitlines()[-1:]}")
    rows = []
    for line in out.stdout.splitlines():
        m = re.match(r"\s*([\d.]+)%\s+(.*)$", line)
        if m:
            rows.append((float(m.group(1)), m.group(2).strip()))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("data", help="perf.data of an lrd-slam run")
    ap.add_argument("--top", type=int, default=12, help="symbols listed per thread")
    ap.add_argument("--main", default="lrdslam", help="the tracking thread's name (the program's)")
    a = ap.parse_args()
    threads = report(a.data, ["--sort", "comm"])
    if not threads:
        sys.exit(f"perf_stages.py: error: {a.data}: no samples")
    print("| thread | share of all samples |\n|---|---|")
    for pct, name in threads:
        print(f"| {name} | {pct:.1f} % |")
    symbols = report(a.data, ["--comm", a.main, "--sort", "dso,symbol"])
    totals = {name: 0.0 for name, _ in STAGES}
    other = 0.0
    for pct, sym in symbols:
        for name, pattern in STAGES:
            if re.search(pattern, sym):
                totals[name] += pct
                break
        else:
            other += pct
    print(f"\nTracking thread ({a.main}) by stage:\n\n| stage | share of the thread |\n|---|---|")
    for name, _ in STAGES:
        print(f"| {name} | {totals[name]:.1f} % |")
    print(f"| other (libraries without symbols, libstdc++) | {other:.1f} % |")
    for pct, name in threads:
        rows = report(a.data, ["--comm", name, "--sort", "dso,symbol"])[: a.top]
        print(f"\nTop of {name}:\n\n| share | where |\n|---|---|")
        for p, sym in rows:
            sym = re.sub(r"\s+-\s+-\s*$", "", sym)
            sym = re.sub(r"\s+", " ", sym)
            print(f"| {p:.1f} % | `{sym[:110]}` |")


if __name__ == "__main__":
    main()
