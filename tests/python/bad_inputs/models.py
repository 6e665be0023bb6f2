"""Bad-input cases: the vocabulary and the ONNX segmentation model."""
import struct
from pathlib import Path

from bad_inputs.registry import case, flip, make_dir, replace

# ---------------------------------------------------------------------------------------------
# 5. Vocabulary (header: 8-byte magic, u32 version, k, levels, nodes, words; 48-byte nodes)

VOCAB = Path(__file__).resolve().parents[3] / "vocab" / "orb_vocab.lrdv"
HEADER, NODE = 28, 48
VOCAB_EDITS = {
    "empty": lambda d: b"",
    "truncated-half": lambda d: d[:len(d) // 2],
    "one-byte-appended": lambda d: d + b"\0",
    "bitflip-magic": lambda d: flip(d, 0, 1),
    "bitflip-version": lambda d: flip(d, 8, 3),
    "levels-huge": lambda d: d[:16] + b"\xff\xff\xff\x7f" + d[20:],
    "bitflip-node-count": lambda d: flip(d, 23, 7),
    "node-weight-nan": lambda d: d[:HEADER + NODE + 40] + struct.pack("<d", float("nan")) + d[HEADER + 2 * NODE:],
    "node-parent-forward": lambda d: d[:HEADER + NODE * 5] + struct.pack("<I", 7) + d[HEADER + NODE * 5 + 4:],
}


def vocab_case(id_, make):
    def prepare(ctx):
        f = ctx.tmp / "bad.lrdv"
        make(f)
        return ["--vocabulary", f], f.name

    case(f"vocabulary-{id_}", prepare)


for id_, edit in VOCAB_EDITS.items():
    vocab_case(id_, lambda f, edit=edit: replace(f, edit(VOCAB.read_bytes())))
vocab_case("is-a-folder", make_dir)

# ---------------------------------------------------------------------------------------------
# 6. ONNX segmentation model (--mode semantic --segmenter fnet --segmenter-model FILE)

MODEL = Path(__file__).resolve().parents[3] / "models" / "fnet-lite.onnx"


def onnx_case(id_, make):
    def prepare(ctx):
        f = ctx.tmp / "bad.onnx"
        make(f)
        return ["--mode", "semantic", "--segmenter", "fnet", "--segmenter-model", f], f.name

    case(f"onnx-{id_}", prepare)


for id_, edit in {
    "empty": lambda d: b"",
    "truncated-half": lambda d: d[:len(d) // 2],
    "bitflip-first-tag": lambda d: flip(d, 0, 7),
}.items():
    onnx_case(id_, lambda f, edit=edit: replace(f, edit(MODEL.read_bytes())))
onnx_case("is-a-vocabulary", lambda f: replace(f, VOCAB.read_bytes()[:200000]))
onnx_case("is-a-folder", make_dir)

