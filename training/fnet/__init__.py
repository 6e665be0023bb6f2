"""FNet: the LRD-SLAM paper's lightweight Ghost-ResNet semantic segmentation network (section 2.6)."""
from .ghost import GhostBottleneck, GhostModule, ghost_param_count
from .model import CONFIGS, FNet, FNetConfig, VOC_CLASSES, build_model, count_params, get_config

__all__ = ["GhostModule", "GhostBottleneck", "ghost_param_count", "FNet", "FNetConfig", "CONFIGS",
           "VOC_CLASSES", "build_model", "count_params", "get_config"]
