"""Converts a TFLite model (MediaPipe selfie segmentation) to ONNX that OpenCV 4.6 DNN runs: NCHW float32 input."""
import argparse
import collections
import os
import sys

import onnx

from . import schema
from .convert import convert, op_names


def main(argv=None):
    p = argparse.ArgumentParser(prog="python3 -m tools.tflite2onnx", description=__doc__)
    p.add_argument("input", help="TFLite model (.tflite)")
    p.add_argument("output", help="ONNX model to write")
    p.add_argument("--input-name", default="input", help="name of the ONNX input (default: input)")
    p.add_argument("--output-name", default="output", help="name of the ONNX output (default: output)")
    p.add_argument("-v", "--verbose", action="store_true", help="print the model's operator summary")
    args = p.parse_args(argv)

    try:
        with open(args.input, "rb") as f:
            data = f.read()
        if args.verbose:
            counts = collections.Counter(op_names(schema.Model.from_bytes(data)))
            print(f"{args.input}: " + ", ".join(f"{n} x{c}" for n, c in sorted(counts.items())))
        model = convert(data, args.input_name, args.output_name)
    except (OSError, ValueError) as e:  # unreadable, not a TFLite file, or unsupported (UnsupportedError)
        print(f"tflite2onnx: {args.input}: {e}", file=sys.stderr)
        return 2
    # Write next to the target, then rename, so an interrupted run leaves no half-written model.
    tmp = f"{args.output}.tmp"
    onnx.save(model, tmp)
    os.replace(tmp, args.output)
    if args.verbose:
        print(f"{args.output}: {len(model.graph.node)} ONNX nodes, opset {model.opset_import[0].version}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
