"""Converts MediaPipe's TFLite selfie-segmentation models to ONNX that OpenCV 4.6 DNN runs.

Run from the repository root: /usr/bin/python3 -m tools.tflite2onnx IN.tflite OUT.onnx [--input-name input]
"""
from .convert import convert, op_names
from .ops import UnsupportedError, dequantize_fp16, same_pads

__all__ = ["convert", "op_names", "UnsupportedError", "dequantize_fp16", "same_pads"]
