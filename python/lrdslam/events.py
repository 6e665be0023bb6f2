"""What System.subscribe(callback) delivers, on the publisher's thread, in order: each event has a
`kind` ("frame", "keyframe", "loop", "map", "dense") and the fields of its class here."""
from ._core import events as _events

FrameTracked = _events.FrameTracked
KeyframeInserted = _events.KeyframeInserted
LoopClosed = _events.LoopClosed
MapChanged = _events.MapChanged
DenseMapUpdated = _events.DenseMapUpdated

__all__ = ["FrameTracked", "KeyframeInserted", "LoopClosed", "MapChanged", "DenseMapUpdated"]
