"""TFLite operators -> ONNX nodes (opset 11), for the operators MediaPipe's selfie-segmentation models use.

Every rank-4 activation is kept NCHW on the ONNX side, so NHWC weights and axes are rearranged here.
Each converter gets the converter context `ctx` (see convert.py) and the TFLite operator `op`.
"""
import struct

import numpy as np

from .schema import ACTIVATIONS, PADDING


class UnsupportedError(ValueError):
    """The model uses something this converter does not translate."""


def same_pads(in_size, kernel, stride, dilation=1):
    """TFLite/TensorFlow SAME padding along one axis: (before, after); the odd pixel goes after."""
    out = -(-in_size // stride)
    total = max((out - 1) * stride + (kernel - 1) * dilation + 1 - in_size, 0)
    return total // 2, total - total // 2


def dequantize_fp16(raw, shape):
    """A float16 constant buffer (little-endian) as a float32 array of `shape`."""
    return np.frombuffer(raw, dtype="<f2").astype(np.float32).reshape(shape)


def _spatial_pads(ctx, op, padding, kernel, stride, dilation=(1, 1)):
    """ONNX `pads` [top, left, bottom, right] for a TFLite padding mode on the op's input."""
    if padding == "VALID":
        return [0, 0, 0, 0]
    _, h, w, _ = ctx.shape(op.inputs[0])
    (t, b), (l, r) = (same_pads(h, kernel[0], stride[0], dilation[0]),
                      same_pads(w, kernel[1], stride[1], dilation[1]))
    return [t, l, b, r]


def _activation(ctx, name, code, out_idx):
    """Applies a fused activation to `name` and binds the result to TFLite tensor `out_idx`."""
    act = ACTIVATIONS.get(code, f"#{code}")
    if act == "NONE":
        ctx.bind(out_idx, name)
    elif act == "RELU":
        ctx.node("Relu", [name], out_idx)
    elif act == "RELU6":
        # 6 * clamp(x / 6, 0, 1): OpenCV 4.6 imports Clip only in its pre-opset-11 form (bounds as
        # attributes), which an opset-11 model cannot hold.
        y = ctx.node("HardSigmoid", [name], alpha=1.0 / 6.0, beta=0.0)
        ctx.node("Mul", [y, ctx.const_input(np.float32(6))], out_idx)
    else:
        raise UnsupportedError(f"fused activation {act} is not supported")


def _padding(code):
    if code not in PADDING:
        raise UnsupportedError(f"padding mode #{code} is not supported")
    return PADDING[code]


def _bias(ctx, op, channels):
    if len(op.inputs) > 2 and op.inputs[2] >= 0:
        return ctx.const_input(ctx.constant(op.inputs[2]).reshape(channels))
    return ctx.const_input(np.zeros(channels, np.float32))


def conv_2d(ctx, op):
    # Conv2DOptions: padding, stride_w, stride_h, fused_activation_function, dilation_w, dilation_h
    o = op.builtin_options
    padding, stride, act = _padding(o.byte(0)), (o.int(2), o.int(1)), o.byte(3)
    dilation = (o.int(5, 1), o.int(4, 1))
    w = ctx.constant(op.inputs[1])  # OHWI
    out_c, kh, kw, in_c = w.shape
    groups = ctx.shape(op.inputs[0])[3] // in_c  # grouped conv: input channels a multiple of I
    weights = ctx.const_input(w.transpose(0, 3, 1, 2))
    y = ctx.node("Conv", [ctx.value(op.inputs[0]), weights, _bias(ctx, op, out_c)],
                 kernel_shape=[kh, kw], strides=list(stride), dilations=list(dilation), group=groups,
                 pads=_spatial_pads(ctx, op, padding, (kh, kw), stride, dilation))
    _activation(ctx, y, act, op.outputs[0])


def depthwise_conv_2d(ctx, op):
    # DepthwiseConv2DOptions: padding, stride_w, stride_h, depth_multiplier, activation, dilation_w, dilation_h
    o = op.builtin_options
    padding, stride, act = _padding(o.byte(0)), (o.int(2), o.int(1)), o.byte(4)
    dilation = (o.int(6, 1), o.int(5, 1))
    w = ctx.constant(op.inputs[1])  # 1 x H x W x (in_channels * multiplier)
    _, kh, kw, out_c = w.shape
    in_c = ctx.shape(op.inputs[0])[3]
    # Output channel c reads input channel c // multiplier (so depth_multiplier itself is not needed):
    # an ONNX grouped conv with one group per input channel and weights O x 1 x H x W.
    weights = ctx.const_input(w.transpose(3, 0, 1, 2))
    y = ctx.node("Conv", [ctx.value(op.inputs[0]), weights, _bias(ctx, op, out_c)],
                 kernel_shape=[kh, kw], strides=list(stride), dilations=list(dilation), group=in_c,
                 pads=_spatial_pads(ctx, op, padding, (kh, kw), stride, dilation))
    _activation(ctx, y, act, op.outputs[0])


def transpose_conv_bias(ctx, op):
    """MediaPipe's custom Convolution2DTransposeBias (mediapipe/util/tflite/operations/transpose_conv_bias.cc).

    Custom options are a raw TfLiteTransposeConvParams {padding (1 SAME, 2 VALID), stride_w, stride_h}.
    The kernel scatters input (y, x) to output (y * stride - pad_before + ky, ...) with no kernel flip,
    where SAME gives total = max(0, k - (in - 1) % stride - 1), before = total // 2: ONNX ConvTranspose.
    """
    if len(op.custom_options) < 12:
        raise UnsupportedError("Convolution2DTransposeBias: custom options shorter than 12 bytes")
    padding, stride_w, stride_h = struct.unpack_from("<3i", op.custom_options)
    if padding not in (1, 2):
        raise UnsupportedError(f"Convolution2DTransposeBias: padding #{padding} is not supported")
    w = ctx.constant(op.inputs[1])  # OHWI
    out_c, kh, kw, _ = w.shape
    _, h, wd, _ = ctx.shape(op.inputs[0])
    before, after = [], []
    for size, k, s in ((h, kh, stride_h), (wd, kw, stride_w)):
        total = max(0, k - (size - 1) % s - 1) if padding == 1 else 0
        before.append(total // 2)
        after.append(total - total // 2)
    inputs = [ctx.value(op.inputs[0]), ctx.const_input(w.transpose(3, 0, 1, 2)),  # I x O x H x W
              ctx.const_input(ctx.constant(op.inputs[2]).reshape(out_c))]
    attrs = dict(kernel_shape=[kh, kw], strides=[stride_h, stride_w], pads=before + before)
    if before == after:
        ctx.node("ConvTranspose", inputs, op.outputs[0], **attrs)
        return
    # OpenCV 4.6 rejects asymmetric deconvolution pads: crop `before` on both sides, then slice off the rest.
    y = ctx.node("ConvTranspose", inputs, **attrs)
    starts, ends, axes = ([0, 0], ctx.shape(op.outputs[0])[1:3], [2, 3])
    ctx.node("Slice", [y] + [ctx.const_input(np.array(v, np.int64)) for v in (starts, ends, axes)], op.outputs[0])


def average_pool_2d(ctx, op):
    # Pool2DOptions: padding, stride_w, stride_h, filter_width, filter_height, fused_activation_function
    o = op.builtin_options
    padding, stride, kernel, act = _padding(o.byte(0)), (o.int(2), o.int(1)), (o.int(4), o.int(3)), o.byte(5)
    _, h, w, _ = ctx.shape(op.inputs[0])
    x = ctx.value(op.inputs[0])
    if padding == "VALID" and kernel == (h, w):
        y = ctx.node("GlobalAveragePool", [x])
    else:
        # TFLite divides by the number of in-image pixels under the window: count_include_pad = 0.
        y = ctx.node("AveragePool", [x], kernel_shape=list(kernel), strides=list(stride),
                     pads=_spatial_pads(ctx, op, padding, kernel, stride), count_include_pad=0)
    _activation(ctx, y, act, op.outputs[0])


def mean(ctx, op):
    # ReducerOptions: keep_dims. The models average over height and width only (squeeze-excitation).
    keep_dims = op.builtin_options.bool(0) if op.builtin_options else False
    axes = sorted({int(a) % 4 for a in ctx.constant(op.inputs[1]).reshape(-1)})
    if len(ctx.shape(op.inputs[0])) != 4 or axes != [1, 2] or not keep_dims:
        raise UnsupportedError("MEAN is supported over height and width of a rank-4 tensor, with keep_dims")
    ctx.node("GlobalAveragePool", [ctx.value(op.inputs[0])], op.outputs[0])


def _binary(onnx_op):
    def convert(ctx, op):
        # AddOptions / MulOptions: fused_activation_function
        act = op.builtin_options.byte(0) if op.builtin_options else 0
        y = ctx.node(onnx_op, [ctx.value(op.inputs[0]), ctx.value(op.inputs[1])])
        _activation(ctx, y, act, op.outputs[0])
    return convert


def _unary(onnx_op):
    def convert(ctx, op):
        ctx.node(onnx_op, [ctx.value(op.inputs[0])], op.outputs[0])
    return convert


def hard_swish(ctx, op):
    # x * relu6(x + 3) / 6 == x * HardSigmoid(x) with alpha 1/6, beta 0.5 (OpenCV 4.6 has no HardSwish).
    x = ctx.value(op.inputs[0])
    ctx.node("Mul", [x, ctx.node("HardSigmoid", [x], alpha=1.0 / 6.0, beta=0.5)], op.outputs[0])


def resize_bilinear(ctx, op):
    # ResizeBilinearOptions: new_height (deprecated), new_width (deprecated), align_corners, half_pixel_centers
    o = op.builtin_options
    align_corners, half_pixel = (o.bool(2), o.bool(3)) if o else (False, False)
    if align_corners and half_pixel:
        raise UnsupportedError("RESIZE_BILINEAR with both align_corners and half_pixel_centers")
    # TFLite samples at (out + 0.5) * in / out_size - 0.5 with half_pixel_centers, at out * in / out_size
    # with neither flag; both clamp the two taps into the image, which gives what ONNX's clamped source
    # coordinate gives. align_corners scales by (in - 1) / (out_size - 1) in both.
    mode = "align_corners" if align_corners else "half_pixel" if half_pixel else "asymmetric"
    n, _, _, c = ctx.shape(op.inputs[0])
    out_h, out_w = (int(v) for v in ctx.constant(op.inputs[1]).reshape(2))
    # Opset 11 takes either scales or sizes, the other given as an empty tensor; sizes are exact.
    empty = ctx.const_input(np.zeros(0, np.float32))
    sizes = ctx.const_input(np.array([n, c, out_h, out_w], np.int64))
    ctx.node("Resize", [ctx.value(op.inputs[0]), empty, empty, sizes], op.outputs[0],
             mode="linear", coordinate_transformation_mode=mode)


# TFLite operator name (schema.BUILTIN_OPS or the custom code) -> converter.
# DEQUANTIZE is not here: the converter folds it into constants before translating (convert.py).
CONVERTERS = {
    "ADD": _binary("Add"),
    "AVERAGE_POOL_2D": average_pool_2d,
    "CONV_2D": conv_2d,
    "Convolution2DTransposeBias": transpose_conv_bias,
    "DEPTHWISE_CONV_2D": depthwise_conv_2d,
    "HARD_SWISH": hard_swish,
    "LOGISTIC": _unary("Sigmoid"),
    "MEAN": mean,
    "MUL": _binary("Mul"),
    "RELU": _unary("Relu"),
    "RESIZE_BILINEAR": resize_bilinear,
}
