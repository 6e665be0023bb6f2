"""Read-only accessors for the TFLite flatbuffer (tensorflow/lite/schema/schema.fbs, schema version 3).

Only the tables and fields the converter needs. A field is addressed by its slot: the position of the
field in the table's declaration, counting a union as two slots (its type tag, then its value).
"""
import flatbuffers
import numpy as np
from flatbuffers import number_types as nt

# BuiltinOperator values (schema.fbs enum BuiltinOperator); only the names are used for messages.
BUILTIN_OPS = {
    0: "ADD", 1: "AVERAGE_POOL_2D", 2: "CONCATENATION", 3: "CONV_2D", 4: "DEPTHWISE_CONV_2D",
    5: "DEPTH_TO_SPACE", 6: "DEQUANTIZE", 9: "FULLY_CONNECTED", 14: "LOGISTIC", 17: "MAX_POOL_2D",
    18: "MUL", 19: "RELU", 21: "RELU6", 22: "RESHAPE", 23: "RESIZE_BILINEAR", 25: "SOFTMAX",
    28: "TANH", 32: "CUSTOM", 34: "PAD", 39: "TRANSPOSE", 40: "MEAN", 41: "SUB", 42: "DIV",
    54: "PRELU", 67: "TRANSPOSE_CONV", 97: "RESIZE_NEAREST_NEIGHBOR", 117: "HARD_SWISH",
}
CUSTOM = 32

FLOAT32, FLOAT16 = 0, 1  # TensorType
# TensorType -> numpy dtype (little-endian, as TFLite stores buffers).
TENSOR_TYPES = {FLOAT32: np.dtype("<f4"), FLOAT16: np.dtype("<f2"), 2: np.dtype("<i4"), 3: np.dtype("u1"),
                4: np.dtype("<i8"), 6: np.dtype("?"), 7: np.dtype("<i2"), 9: np.dtype("i1")}

PADDING = {0: "SAME", 1: "VALID"}
ACTIVATIONS = {0: "NONE", 1: "RELU", 2: "RELU_N1_TO_1", 3: "RELU6", 4: "TANH", 5: "SIGN_BIT"}


class _Table:
    """A flatbuffer table with slot-based field access."""

    def __init__(self, buf, pos):
        self._buf = buf
        self._tab = flatbuffers.table.Table(buf, pos)

    def _offset(self, slot):
        return self._tab.Offset(4 + 2 * slot)

    def _scalar(self, slot, flags, default=0):
        o = self._offset(slot)
        return self._tab.Get(flags, self._tab.Pos + o) if o else default

    def _ints(self, slot):
        o = self._offset(slot)
        return self._tab.GetVectorAsNumpy(nt.Int32Flags, o).tolist() if o else []

    def _bytes(self, slot):
        o = self._offset(slot)
        if not o:
            return b""
        start = self._tab.Vector(o)
        return bytes(self._buf[start:start + self._tab.VectorLen(o)])

    def _string(self, slot):
        o = self._offset(slot)
        return self._tab.String(self._tab.Pos + o).decode("utf-8") if o else ""

    def _table(self, slot, cls):
        o = self._offset(slot)
        return cls(self._buf, self._tab.Indirect(self._tab.Pos + o)) if o else None

    def _tables(self, slot, cls):
        o = self._offset(slot)
        if not o:
            return []
        start = self._tab.Vector(o)
        return [cls(self._buf, self._tab.Indirect(start + 4 * i)) for i in range(self._tab.VectorLen(o))]


class Options(_Table):
    """Any builtin-options table; the op converter knows which one it is and reads fields by slot."""

    def int(self, slot, default=0):
        return self._scalar(slot, nt.Int32Flags, default)

    def byte(self, slot, default=0):
        return self._scalar(slot, nt.Int8Flags, default)

    def bool(self, slot):
        return bool(self._scalar(slot, nt.BoolFlags, False))

    def ints(self, slot):
        return self._ints(slot)


class OperatorCode(_Table):
    @property
    def builtin_code(self):
        # Old files fill only the byte field (deprecated_builtin_code); newer ones also the int field,
        # with the byte field at 127 for codes that do not fit: the larger is the code (as TFLite reads it).
        return max(self._scalar(0, nt.Int8Flags), self._scalar(3, nt.Int32Flags))

    @property
    def custom_code(self):
        return self._string(1)

    @property
    def name(self):
        code = self.builtin_code
        if code == CUSTOM:
            return self.custom_code
        return BUILTIN_OPS.get(code, f"builtin #{code}")


class Operator(_Table):
    @property
    def opcode_index(self):
        return self._scalar(0, nt.Uint32Flags)

    @property
    def inputs(self):
        return self._ints(1)

    @property
    def outputs(self):
        return self._ints(2)

    @property
    def builtin_options(self):
        # slot 3 is the union's type tag, slot 4 its table
        return self._table(4, Options)

    @property
    def custom_options(self):
        return self._bytes(5)


class Tensor(_Table):
    @property
    def shape(self):
        return self._ints(0)

    @property
    def type(self):
        return self._scalar(1, nt.Int8Flags)

    @property
    def buffer(self):
        return self._scalar(2, nt.Uint32Flags)

    @property
    def name(self):
        return self._string(3)


class SubGraph(_Table):
    @property
    def tensors(self):
        return self._tables(0, Tensor)

    @property
    def inputs(self):
        return self._ints(1)

    @property
    def outputs(self):
        return self._ints(2)

    @property
    def operators(self):
        return self._tables(3, Operator)


class Buffer(_Table):
    def data(self, file_bytes):
        # Files over 2 GB keep the data after the flatbuffer (offset/size); others inline it.
        offset = self._scalar(1, nt.Uint64Flags)
        if offset > 1:
            return bytes(file_bytes[offset:offset + self._scalar(2, nt.Uint64Flags)])
        return self._bytes(0)


class Model(_Table):
    @classmethod
    def from_bytes(cls, data):
        if len(data) < 8 or data[4:8] != b"TFL3":
            raise ValueError("not a TFLite flatbuffer (file identifier TFL3 missing)")
        return cls(data, flatbuffers.encode.Get(nt.UOffsetTFlags.packer_type, data, 0))

    @property
    def version(self):
        return self._scalar(0, nt.Uint32Flags)

    @property
    def operator_codes(self):
        return self._tables(1, OperatorCode)

    @property
    def subgraphs(self):
        return self._tables(2, SubGraph)

    @property
    def buffers(self):
        return self._tables(4, Buffer)
