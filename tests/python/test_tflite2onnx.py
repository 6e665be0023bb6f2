"""tools.tflite2onnx: padding and float16 helpers, clear errors, a synthetic TFLite graph checked against a
NumPy implementation of the TFLite kernels, and MediaPipe's selfie models (cached by scripts/fetch-models.sh)
against the reference ONNX and reference masks in ../shared. OpenCV DNN runs every converted model."""
import glob
import os
import struct
import sys

import numpy as np
import pytest

cv2 = pytest.importorskip("cv2", reason="python3-opencv not installed (scripts/install-deps.sh)")
flatbuffers = pytest.importorskip("flatbuffers", reason="python3-flatbuffers not installed (scripts/install-deps.sh)")
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, ROOT)

from tools.tflite2onnx import UnsupportedError, convert, dequantize_fp16, same_pads  # noqa: E402
from tools.tflite2onnx import schema  # noqa: E402
from tools.tflite2onnx.__main__ import main as cli_main  # noqa: E402

SHARED = os.environ.get("LRD_SHARED_DIR") or os.path.join(ROOT, "..", "shared")
CACHE = os.path.join(ROOT, "data", "models", "npm")
MODELS = {  # cached tflite -> (reference ONNX in shared/models/mediapipe_selfie, blob size W x H)
    "selfie_segmentation": ("selfie_segmentation_256x256.onnx", (256, 256)),
    "selfie_segmentation_landscape": ("selfie_segmentation_landscape_256x144.onnx", (256, 144)),
}


# ---------------------------------------------------------------------------------------------------
# A minimal TFLite writer (schema.fbs slots) for synthetic graphs.

CODES = {name: code for code, name in schema.BUILTIN_OPS.items()}
OPTION_TAGS = {"Conv2D": 1, "DepthwiseConv2D": 2, "Pool2D": 5, "Add": 11, "ResizeBilinear": 15, "Mul": 21,
               "Reducer": 27}  # BuiltinOptions union tags


def _table(b, fields):
    """fields: (slot, flatbuffers.Builder Prepend*Slot suffix, value); children must be built already."""
    b.StartObject(max(slot for slot, _, _ in fields) + 1 if fields else 0)
    for slot, kind, value in fields:
        getattr(b, f"Prepend{kind}Slot")(slot, value, None)
    return b.EndObject()


def _offsets(b, offs):
    b.StartVector(4, len(offs), 4)
    for o in reversed(offs):
        b.PrependUOffsetTRelative(o)
    return b.EndVector()


def tensor(name, shape, value=None, ttype=schema.FLOAT32):
    return name, shape, ttype, value


def op(name, inputs, outputs, options_kind=None, options=(), custom=b""):
    """name: a BuiltinOperator name or a custom code; options: (slot, Prepend*Slot suffix, value)."""
    return name, inputs, outputs, options_kind, options, custom


def build_tflite(tensors, ops, inputs, outputs):
    """A TFLite flatbuffer with one subgraph; ops, inputs and outputs name their tensors."""
    b = flatbuffers.Builder(1024)
    index = {t[0]: i for i, t in enumerate(tensors)}
    ints = lambda names: b.CreateNumpyVector(np.array([index[n] for n in names], np.int32))  # noqa: E731
    codes = list(dict.fromkeys(name for name, *_ in ops))
    buffers = [_table(b, [])]  # buffer 0: the empty sentinel
    tensor_offs = []
    for name, shape, ttype, value in tensors:
        fields = [(0, "UOffsetTRelative", b.CreateNumpyVector(np.array(shape, np.int32))), (1, "Int8", ttype),
                  (3, "UOffsetTRelative", b.CreateString(name))]
        if value is not None:
            data = b.CreateNumpyVector(np.frombuffer(np.ascontiguousarray(value).tobytes(), np.uint8))
            buffers.append(_table(b, [(0, "UOffsetTRelative", data)]))
            fields.append((2, "Uint32", len(buffers) - 1))
        tensor_offs.append(_table(b, fields))
    op_offs = []
    for name, ins, outs, kind, options, custom in ops:
        fields = [(0, "Uint32", codes.index(name)), (1, "UOffsetTRelative", ints(ins)),
                  (2, "UOffsetTRelative", ints(outs))]
        if kind:
            fields += [(3, "Uint8", OPTION_TAGS[kind]), (4, "UOffsetTRelative", _table(b, list(options)))]
        if custom:
            fields.append((5, "UOffsetTRelative", b.CreateNumpyVector(np.frombuffer(custom, np.uint8))))
        op_offs.append(_table(b, fields))
    code_offs = []
    for name in codes:
        if name in CODES:
            code_offs.append(_table(b, [(0, "Int8", min(CODES[name], 127)), (3, "Int32", CODES[name])]))
        else:
            code_offs.append(_table(b, [(0, "Int8", schema.CUSTOM), (1, "UOffsetTRelative", b.CreateString(name)),
                                        (3, "Int32", schema.CUSTOM)]))
    subgraph = _table(b, [(0, "UOffsetTRelative", _offsets(b, tensor_offs)), (1, "UOffsetTRelative", ints(inputs)),
                          (2, "UOffsetTRelative", ints(outputs)), (3, "UOffsetTRelative", _offsets(b, op_offs))])
    model = _table(b, [(0, "Uint32", 3), (1, "UOffsetTRelative", _offsets(b, code_offs)),
                       (2, "UOffsetTRelative", _offsets(b, [subgraph])),
                       (4, "UOffsetTRelative", _offsets(b, buffers))])
    b.Finish(model, file_identifier=b"TFL3")
    return bytes(b.Output())


# ---------------------------------------------------------------------------------------------------
# TFLite kernels in NumPy (NHWC, float64), written from the TFLite reference kernels and MediaPipe's
# transpose_conv_bias.cc: windows start at out * stride - pad_before, out-of-image taps read zero.

def _pad_before(in_size, k, s, d, padding):
    """(padding before the first pixel, output size) along one axis, as TFLite's ComputePadding gives them."""
    if padding == 1:  # VALID
        return 0, -(-(in_size - (k - 1) * d) // s)
    out = -(-in_size // s)
    return max((out - 1) * s + (k - 1) * d + 1 - in_size, 0) // 2, out


def _taps(x, oy, ox):
    """x[:, oy, ox] with zeros where the indices leave the image."""
    h, w = x.shape[1:3]
    vy, vx = (oy >= 0) & (oy < h), (ox >= 0) & (ox < w)
    t = x[:, np.clip(oy, 0, h - 1)][:, :, np.clip(ox, 0, w - 1)]
    return t * (vy[:, None] & vx[None, :])[None, :, :, None]


def np_conv(x, w, bias, stride, dil, padding, depthwise):
    (sh, sw), (dh, dw) = stride, dil
    kh, kw = w.shape[1:3]
    (ph, oh), (pw, ow) = _pad_before(x.shape[1], kh, sh, dh, padding), _pad_before(x.shape[2], kw, sw, dw, padding)
    out = np.zeros((x.shape[0], oh, ow, w.shape[3] if depthwise else w.shape[0])) + bias
    for ky in range(kh):
        for kx in range(kw):
            t = _taps(x, np.arange(oh) * sh - ph + ky * dh, np.arange(ow) * sw - pw + kx * dw)
            if depthwise:  # output channel c reads input channel c // multiplier
                out += np.repeat(t, w.shape[3] // x.shape[3], axis=3) * w[0, ky, kx]
            else:
                out += t @ w[:, ky, kx, :].T
    return out


def np_transpose_conv_bias(x, w, bias, padding, stride_w, stride_h):
    """Input (y, x) adds x * w[:, ky, kx] at output (y * stride - before + ky, ...); padding 1 is SAME."""
    (n, h, wd, _), (oc, kh, kw, _) = x.shape, w.shape
    (sh, sw) = stride_h, stride_w
    full = np.zeros((n, (h - 1) * sh + kh, (wd - 1) * sw + kw, oc))  # before cropping the padding
    for ky in range(kh):
        for kx in range(kw):
            full[:, ky:ky + (h - 1) * sh + 1:sh, kx:kx + (wd - 1) * sw + 1:sw] += x @ w[:, ky, kx].T
    tot_h = max(0, kh - (h - 1) % sh - 1) if padding == 1 else 0
    tot_w = max(0, kw - (wd - 1) % sw - 1) if padding == 1 else 0
    out_h, out_w = full.shape[1] - tot_h, full.shape[2] - tot_w
    return full[:, tot_h // 2:tot_h // 2 + out_h, tot_w // 2:tot_w // 2 + out_w] + bias


def np_avg_pool(x, k, s, padding):
    (ph, oh), (pw, ow) = (_pad_before(x.shape[1], k[0], s[0], 1, padding),
                          _pad_before(x.shape[2], k[1], s[1], 1, padding))
    out = np.zeros((x.shape[0], oh, ow, x.shape[3]))
    for y in range(oh):
        for xx in range(ow):
            y0, x0 = y * s[0] - ph, xx * s[1] - pw
            win = x[:, max(y0, 0):min(y0 + k[0], x.shape[1]), max(x0, 0):min(x0 + k[1], x.shape[2])]
            out[:, y, xx] = win.mean(axis=(1, 2))  # over in-image taps only
    return out


def np_resize_bilinear(x, out_h, out_w, align_corners, half_pixel):
    def axis(in_size, out_size):
        scale = np.float32(in_size / out_size)
        if align_corners and out_size > 1:
            scale = np.float32((in_size - 1) / (out_size - 1))
        v = np.arange(out_size, dtype=np.float32)
        src = (v + np.float32(0.5)) * scale - np.float32(0.5) if half_pixel else v * scale
        lo = np.maximum(np.floor(src), 0).astype(int)
        hi = np.minimum(np.ceil(src), in_size - 1).astype(int)
        return lo, hi, (src - lo).astype(np.float64)  # weights from the clamped lower index, as TFLite does
    (y0, y1, fy), (x0, x1, fx) = axis(x.shape[1], out_h), axis(x.shape[2], out_w)
    fy, fx = fy[None, :, None, None], fx[None, None, :, None]
    rows = lambda r: x[:, r][:, :, x0] * (1 - fx) + x[:, r][:, :, x1] * fx  # noqa: E731
    return rows(y0) * (1 - fy) + rows(y1) * fy


ACT = {0: lambda v: v, 1: lambda v: np.maximum(v, 0), 3: lambda v: np.clip(v, 0, 6)}


def np_run_tflite(data, x):
    """Runs the main subgraph of a TFLite model in NumPy on NHWC input x; returns the outputs (NHWC)."""
    model = schema.Model.from_bytes(data)
    sg, codes, buffers = model.subgraphs[0], model.operator_codes, model.buffers
    vals = {}
    for i, t in enumerate(sg.tensors):
        raw = buffers[t.buffer].data(data)
        if raw:
            vals[i] = np.frombuffer(raw, schema.TENSOR_TYPES[t.type]).reshape(t.shape)
    vals[sg.inputs[0]] = x.astype(np.float64)
    for op in sg.operators:
        name, o, i = codes[op.opcode_index].name, op.builtin_options, op.inputs
        a = vals[i[0]]
        if name == "DEQUANTIZE":
            y = a.astype(np.float64)
        elif name in ("CONV_2D", "DEPTHWISE_CONV_2D"):
            dw = int(name == "DEPTHWISE_CONV_2D")  # depthwise options have depth_multiplier at slot 3
            dilation = (o.int(5 + dw, 1), o.int(4 + dw, 1))
            y = ACT[o.byte(3 + dw)](np_conv(a, vals[i[1]], vals[i[2]], (o.int(2), o.int(1)), dilation, o.byte(0), dw))
        elif name == "Convolution2DTransposeBias":
            y = np_transpose_conv_bias(a, vals[i[1]], vals[i[2]], *struct.unpack_from("<3i", op.custom_options))
        elif name == "AVERAGE_POOL_2D":
            y = ACT[o.byte(5)](np_avg_pool(a, (o.int(4), o.int(3)), (o.int(2), o.int(1)), o.byte(0)))
        elif name == "MEAN":
            y = a.mean(axis=tuple(int(v) for v in vals[i[1]]), keepdims=True)
        elif name in ("ADD", "MUL"):
            y = ACT[o.byte(0)](a + vals[i[1]] if name == "ADD" else a * vals[i[1]])
        elif name == "HARD_SWISH":
            y = a * np.clip(a + 3, 0, 6) / 6
        elif name == "LOGISTIC":
            y = 0.5 * (1 + np.tanh(a / 2))  # the logistic function, without overflow
        elif name == "RELU":
            y = np.maximum(a, 0)
        elif name == "RESIZE_BILINEAR":
            y = np_resize_bilinear(a, *(int(v) for v in vals[i[1]]), o.bool(2), o.bool(3))
        else:
            raise NotImplementedError(name)
        assert list(y.shape) == sg.tensors[op.outputs[0]].shape, name
        vals[op.outputs[0]] = y
    return [vals[k] for k in sg.outputs]


def run_opencv(onnx_model, blob):
    net = cv2.dnn.readNetFromONNX(onnx_model.SerializeToString())
    net.setInput(blob.astype(np.float32))
    return net.forward([o.name for o in onnx_model.graph.output])


# ---------------------------------------------------------------------------------------------------
# Unit tests (no downloads)

def test_same_pads_follow_tensorflow():
    # (in, kernel, stride, dilation) -> (before, after): the odd pixel goes after
    cases = {(256, 3, 2, 1): (0, 1), (32, 5, 2, 1): (1, 2), (16, 5, 1, 1): (2, 2), (11, 3, 2, 1): (1, 1),
             (9, 5, 2, 1): (2, 2), (6, 3, 1, 2): (2, 2), (10, 1, 3, 1): (0, 0), (1, 3, 1, 1): (1, 1)}
    for (n, k, s, d), pads in cases.items():
        assert same_pads(n, k, s, d) == pads, (n, k, s, d)
    for n in range(1, 40):
        for k in range(1, 8):
            for s in range(1, 4):
                for d in (1, 2):
                    before, after = same_pads(n, k, s, d)
                    assert 0 <= after - before <= 1
                    assert (n + before + after - (k - 1) * d - 1) // s + 1 == -(-n // s)  # SAME: ceil(n / s) outputs


def test_dequantize_fp16_is_exact():
    half = np.array([0, -0.0, 1, -2.5, 65504, 6.1e-5, 6e-8, np.inf, -np.inf, 0.1], np.float16).reshape(2, 5)
    out = dequantize_fp16(half.tobytes(), (2, 5))
    assert out.dtype == np.float32 and out.shape == (2, 5)
    assert np.array_equal(out, half.astype(np.float32))
    assert np.signbit(out[0, 1]) and out[1, 1] == np.float32(np.float16(6e-8))  # -0 and subnormals kept


def synthetic_model(seed=0):
    """Every translated operator, with odd sizes (asymmetric SAME pads), unequal strides and dilations,
    float16 weights behind DEQUANTIZE, fused RELU/RELU6, a channel-broadcast MUL and three resize modes."""
    r = np.random.RandomState(seed)
    f = lambda *s: r.uniform(-1, 1, s).astype(np.float32)  # noqa: E731
    i32 = lambda *v: tensor(f"size{v}", [len(v)], np.array(v, np.int32), 2)  # noqa: E731 (INT32)
    # Conv2DOptions: padding (0 SAME, 1 VALID), stride_w, stride_h, activation (1 RELU, 3 RELU6), dilation w, h
    conv = lambda pad, sw, sh, act, dw=1, dh=1: [(0, "Int8", pad), (1, "Int32", sw), (2, "Int32", sh),  # noqa: E731
                                                 (3, "Int8", act), (4, "Int32", dw), (5, "Int32", dh)]
    t = [tensor("x", [1, 12, 11, 3]), tensor("w1_f16", [8, 3, 3, 3], f(8, 3, 3, 3).astype(np.float16), schema.FLOAT16),
         tensor("w1", [8, 3, 3, 3]), tensor("b1", [8], f(8)), tensor("a", [1, 6, 6, 8]), tensor("hs", [1, 6, 6, 8]),
         tensor("w2", [1, 3, 3, 16], f(1, 3, 3, 16)), tensor("b2", [16], f(16)), tensor("c", [1, 6, 6, 16]),
         tensor("d", [1, 3, 6, 16]), i32(1, 2), tensor("e", [1, 1, 1, 16]), tensor("sig", [1, 1, 1, 16]),
         tensor("g", [1, 3, 6, 16]), tensor("w3", [4, 4, 3, 16], f(4, 4, 3, 16)), tensor("b3", [4], f(4)),
         tensor("h", [1, 5, 6, 4]), i32(10, 12), tensor("i", [1, 10, 12, 4]), tensor("w4", [4, 1, 1, 4], f(4, 1, 1, 4)),
         tensor("b4", [4], f(4)), tensor("k", [1, 10, 12, 4]), tensor("l", [1, 10, 12, 4]), tensor("cst", [4], f(4)),
         tensor("m", [1, 10, 12, 4]), tensor("out1", [1, 10, 12, 4]), i32(9, 8), tensor("out2", [1, 9, 8, 4]),
         i32(7, 5), tensor("out3", [1, 7, 5, 4]), tensor("w5", [2, 3, 3, 4], f(2, 3, 3, 4)), tensor("b5", [2], f(2)),
         tensor("out4", [1, 4, 8, 2])]
    ops = [op("DEQUANTIZE", ["w1_f16"], ["w1"]),
           op("CONV_2D", ["x", "w1", "b1"], ["a"], "Conv2D", conv(0, 2, 2, 3)),
           op("HARD_SWISH", ["a"], ["hs"]),
           # padding, stride_w, stride_h, depth_multiplier 2, RELU, dilation 2 x 2
           op("DEPTHWISE_CONV_2D", ["hs", "w2", "b2"], ["c"], "DepthwiseConv2D",
              [(0, "Int8", 0), (1, "Int32", 1), (2, "Int32", 1), (3, "Int32", 2), (4, "Int8", 1),
               (5, "Int32", 2), (6, "Int32", 2)]),
           # SAME, stride_w 1, stride_h 2, filter_width 2, filter_height 3
           op("AVERAGE_POOL_2D", ["c"], ["d"], "Pool2D",
              [(0, "Int8", 0), (1, "Int32", 1), (2, "Int32", 2), (3, "Int32", 2), (4, "Int32", 3)]),
           op("MEAN", ["c", "size(1, 2)"], ["e"], "Reducer", [(0, "Bool", True)]),
           op("LOGISTIC", ["e"], ["sig"]),
           op("MUL", ["d", "sig"], ["g"], "Mul"),
           op("Convolution2DTransposeBias", ["g", "w3", "b3"], ["h"], custom=struct.pack("<3i", 1, 1, 2)),
           op("RESIZE_BILINEAR", ["h", "size(10, 12)"], ["i"], "ResizeBilinear", [(3, "Bool", True)]),
           op("CONV_2D", ["i", "w4", "b4"], ["k"], "Conv2D", conv(1, 1, 1, 0)),
           op("ADD", ["i", "k"], ["l"], "Add", [(0, "Int8", 1)]),
           op("ADD", ["l", "cst"], ["m"], "Add"),
           op("RELU", ["m"], ["out1"]),
           op("RESIZE_BILINEAR", ["h", "size(9, 8)"], ["out2"], "ResizeBilinear", [(2, "Bool", True)]),
           op("RESIZE_BILINEAR", ["h", "size(7, 5)"], ["out3"], "ResizeBilinear"),
           op("CONV_2D", ["i", "w5", "b5"], ["out4"], "Conv2D", conv(1, 1, 2, 0, dw=2))]
    return build_tflite(t, ops, ["x"], ["out1", "out2", "out3", "out4"])


def test_synthetic_graph_matches_numpy_tflite_kernels():
    data = synthetic_model()
    model = convert(data)
    x = np.random.RandomState(1).uniform(0, 1, (1, 12, 11, 3)).astype(np.float32)
    outs = run_opencv(model, x.transpose(0, 3, 1, 2))
    refs = np_run_tflite(data, x)
    assert len(outs) == len(refs) == 4
    for out, ref in zip(outs, refs):
        assert out.shape == ref.transpose(0, 3, 1, 2).shape
        assert np.abs(out - ref.transpose(0, 3, 1, 2)).max() < 1e-4


def test_unsupported_operator_is_named(tmp_path, capsys):
    t = [tensor("x", [1, 4, 4, 2]), tensor("y", [1, 4, 4, 2]), tensor("z", [1, 4, 4, 2])]
    data = build_tflite(t, [op("SOFTMAX", ["x"], ["y"]), op("FancyCustomOp", ["y"], ["z"])], ["x"], ["z"])
    with pytest.raises(UnsupportedError, match="unsupported TFLite operator.*FancyCustomOp, SOFTMAX"):
        convert(data)
    src, dst = tmp_path / "m.tflite", tmp_path / "m.onnx"
    src.write_bytes(data)
    assert cli_main([str(src), str(dst)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "SOFTMAX" in err and not dst.exists()
    with pytest.raises(ValueError, match="TFL3"):
        convert(b"not a flatbuffer at all")


# ---------------------------------------------------------------------------------------------------
# MediaPipe's models (scripts/fetch-models.sh caches them) against ../shared

PHOTOS = sorted(glob.glob(os.path.join(SHARED, "data", "people", "*.*")))


def _converted(name, tmp_path):
    """(tflite bytes, converted model written to and read back from tmp_path, reference ONNX path, size)."""
    src = os.path.join(CACHE, f"{name}.tflite")
    ref_file, size = MODELS[name]
    ref = os.path.join(SHARED, "models", "mediapipe_selfie", ref_file)
    if not os.path.isfile(src):
        pytest.skip(f"{src} not cached: run scripts/fetch-models.sh")
    if not os.path.isfile(ref) or not PHOTOS:
        pytest.skip(f"shared reference models and photos not found under {SHARED}")
    dst = tmp_path / f"{name}.onnx"
    assert cli_main([src, str(dst)]) == 0
    with open(src, "rb") as f:
        data = f.read()
    return data, cv2.dnn.readNetFromONNX(str(dst)), cv2.dnn.readNetFromONNX(ref), size


def _blob(photo, size):
    return cv2.dnn.blobFromImage(cv2.imread(photo, cv2.IMREAD_COLOR), 1 / 255.0, size, swapRB=True)


@pytest.mark.parametrize("name", sorted(MODELS))
def test_selfie_model_matches_reference_onnx_and_tflite_kernels(name, tmp_path):
    data, ours, ref, size = _converted(name, tmp_path)
    worst = 0.0
    for photo in PHOTOS:
        blob = _blob(photo, size)
        ours.setInput(blob)
        ref.setInput(blob)
        y = ours.forward()
        assert y.shape == (1, 1, size[1], size[0])
        worst = max(worst, float(np.abs(y - ref.forward()).max()))
    assert worst <= 1e-3, f"max abs difference to the reference ONNX {worst}"
    # The semantics, independently of the reference: the TFLite kernels in NumPy on one photo.
    (expected,) = np_run_tflite(data, blob.transpose(0, 2, 3, 1))
    assert np.abs(y - expected.transpose(0, 3, 1, 2)).max() <= 1e-3


def test_selfie_masks_match_reference_masks(tmp_path):
    _, ours, _, size = _converted("selfie_segmentation", tmp_path)
    for photo in PHOTOS:
        img = cv2.imread(photo, cv2.IMREAD_COLOR)
        ours.setInput(_blob(photo, size))
        prob = cv2.resize(ours.forward()[0, 0], (img.shape[1], img.shape[0]), interpolation=cv2.INTER_LINEAR)
        stem = os.path.splitext(os.path.basename(photo))[0]
        ref = cv2.imread(os.path.join(SHARED, "data", "people", "ref_masks", "selfie_256x256", f"{stem}.png"),
                         cv2.IMREAD_UNCHANGED)
        assert ref is not None and ref.shape == prob.shape, stem
        mask, expected = prob > 0.5, ref != 0
        iou = np.count_nonzero(mask & expected) / max(np.count_nonzero(mask | expected), 1)
        assert iou >= 0.98, f"{stem}: IoU {iou:.4f}"
