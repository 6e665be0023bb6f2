"""The synthetic benchmark's frames, rendered on demand: the frames `lrdslam synth` writes for the
same preset, seed and options (a Sequence, as lrdslam.io.read_sequence returns)."""
from ._core import synth as _synth

presets = _synth.presets
render = _synth.render

__all__ = ["presets", "render"]
