"""Builds the ONNX graph for the main subgraph of a TFLite model."""
import collections

import numpy as np
import onnx
from onnx import TensorProto, helper, numpy_helper

from . import schema
from .ops import CONVERTERS, UnsupportedError, dequantize_fp16

OPSET = 11  # what OpenCV 4.6 DNN imports best (Resize with roi/scales/sizes inputs)


class Context:
    """What an op converter sees: TFLite tensors by index, and ways to add ONNX nodes and constants."""

    def __init__(self, model, data):
        self.subgraph = model.subgraphs[0]
        self.tensors = self.subgraph.tensors
        self.nodes, self.initializers = [], []
        self._names = {}  # TFLite tensor index -> ONNX value name (activations are NCHW when rank 4)
        self._counter = collections.Counter()
        self._constants = {}
        buffers = model.buffers
        for i, t in enumerate(self.tensors):
            raw = buffers[t.buffer].data(data) if t.buffer < len(buffers) else b""
            if raw:
                self._constants[i] = _decode(t, raw)

    def shape(self, idx):
        return self.tensors[idx].shape

    def constant(self, idx):
        """A constant tensor's value in TFLite layout; raises if the tensor is computed at run time."""
        if idx not in self._constants:
            raise UnsupportedError(f"tensor {self.tensors[idx].name!r} must be a constant")
        return self._constants[idx]

    def fold_dequantize(self, op):
        """DEQUANTIZE of a float16 constant (already widened when loaded) is that constant: no node."""
        src, dst = op.inputs[0], op.outputs[0]
        if src not in self._constants or self.tensors[src].type != schema.FLOAT16:
            raise UnsupportedError(f"DEQUANTIZE of {self.tensors[src].name!r}: only float16 constants are supported")
        self._constants[dst] = self._constants[src]

    def bound(self):
        """(TFLite tensor index, ONNX name) of every translated tensor."""
        return self._names.items()

    def _fresh(self, hint):
        self._counter[hint] += 1
        return f"{hint}_{self._counter[hint]}"

    def const_input(self, value):
        name = self._fresh("const")
        self.initializers.append(numpy_helper.from_array(np.asarray(value), name))
        return name

    def value(self, idx):
        """The ONNX name of a TFLite tensor used as an operand (a constant becomes an NCHW initializer)."""
        if idx in self._names:
            return self._names[idx]
        if idx in self._constants:
            v = self.constant(idx)
            if v.ndim == 4:
                v = v.transpose(0, 3, 1, 2)
            elif v.ndim == 1 and v.size > 1:
                v = v.reshape(-1, 1, 1)  # broadcasts over the last NHWC axis = the channel axis of NCHW
            elif v.ndim not in (0, 1):
                raise UnsupportedError(f"constant operand {self.tensors[idx].name!r} of rank {v.ndim}")
            return self.const_input(v)
        raise UnsupportedError(f"tensor {self.tensors[idx].name!r} is used before it is computed")

    def bind(self, idx, name):
        self._names[idx] = name

    def node(self, op_type, inputs, out_idx=None, **attrs):
        """Adds a node; binds its output to TFLite tensor `out_idx` if given. Returns the output name."""
        name = self._fresh(op_type) if out_idx is None else f"t{out_idx}"
        self.nodes.append(helper.make_node(op_type, inputs, [name], name=name, **attrs))
        if out_idx is not None:
            self.bind(out_idx, name)
        return name


def _decode(tensor, raw):
    """A constant buffer as an array of the tensor's shape; float16 weights become float32 (exactly)."""
    if tensor.type == schema.FLOAT16:
        return dequantize_fp16(raw, tensor.shape)
    if tensor.type not in schema.TENSOR_TYPES:
        raise UnsupportedError(f"tensor {tensor.name!r}: type #{tensor.type} is not supported")
    return np.frombuffer(raw, schema.TENSOR_TYPES[tensor.type]).reshape(tensor.shape)


def op_names(model):
    """The operator name of each operator of the main subgraph, in execution order."""
    codes = model.operator_codes
    return [codes[op.opcode_index].name for op in model.subgraphs[0].operators]


def convert(data, input_name="input", output_name="output"):
    """Converts TFLite flatbuffer bytes to an onnx.ModelProto (NCHW float32 input and outputs)."""
    model = schema.Model.from_bytes(data)
    if len(model.subgraphs) != 1:
        raise UnsupportedError(f"{len(model.subgraphs)} subgraphs; only single-subgraph models are supported")
    names = op_names(model)
    unsupported = sorted(set(names) - set(CONVERTERS) - {"DEQUANTIZE"})
    if unsupported:
        raise UnsupportedError(f"unsupported TFLite operator(s): {', '.join(unsupported)}")
    ctx = Context(model, data)
    sg = ctx.subgraph

    inputs = []
    for k, idx in enumerate(sg.inputs):
        t = ctx.tensors[idx]
        if t.type != schema.FLOAT32 or len(t.shape) != 4:
            raise UnsupportedError(f"input {t.name!r}: only rank-4 float32 inputs are supported")
        name = input_name if len(sg.inputs) == 1 else f"{input_name}{k}"
        n, h, w, c = t.shape
        inputs.append(helper.make_tensor_value_info(name, TensorProto.FLOAT, [n, c, h, w]))
        ctx.bind(idx, name)

    for op, name in zip(sg.operators, names):
        if name == "DEQUANTIZE":
            ctx.fold_dequantize(op)
        else:
            CONVERTERS[name](ctx, op)

    outputs = []
    for k, idx in enumerate(sg.outputs):
        t = ctx.tensors[idx]
        name = output_name if len(sg.outputs) == 1 else f"{output_name}{k}"
        shape = [t.shape[a] for a in (0, 3, 1, 2)] if len(t.shape) == 4 else t.shape
        ctx.nodes.append(helper.make_node("Identity", [ctx.value(idx)], [name], name=name))
        outputs.append(helper.make_tensor_value_info(name, TensorProto.FLOAT, shape))

    graph = helper.make_graph(ctx.nodes, "tflite2onnx", inputs, outputs, ctx.initializers)
    onnx_model = helper.make_model(graph, producer_name="lrd-slam tools.tflite2onnx",
                                   opset_imports=[helper.make_opsetid("", OPSET)])
    onnx_model.ir_version = 7  # opset 11 era; readable by OpenCV 4.6 and onnx 1.12
    onnx.checker.check_model(onnx_model)
    _check_shapes(onnx_model, ctx)
    return onnx_model


def _check_shapes(onnx_model, ctx):
    """Every translated tensor must have the shape TFLite declares (NCHW order for rank 4)."""
    inferred = onnx.shape_inference.infer_shapes(onnx_model).graph.value_info
    dims = {v.name: [d.dim_value for d in v.type.tensor_type.shape.dim] for v in inferred}
    for idx, name in ctx.bound():
        if name not in dims:
            continue
        tfl = ctx.shape(idx)
        expected = [tfl[a] for a in (0, 3, 1, 2)] if len(tfl) == 4 else tfl
        if dims[name] != expected:
            raise AssertionError(f"tensor {ctx.tensors[idx].name!r}: ONNX shape {dims[name]} != TFLite {expected}")
