"""Recorded sequences as `lrdslam run` reads them: TUM-layout folders (TUM RGB-D, Bonn, our
synthetic benchmark) and bags. Frames are decoded on demand: seq[i], len(seq), `for f in seq`."""
from ._core import io as _io

Frame = _io.Frame
Sequence = _io.Sequence
read_sequence = _io.read_sequence

__all__ = ["Frame", "Sequence", "read_sequence"]
