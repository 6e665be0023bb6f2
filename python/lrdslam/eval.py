"""ATE and RPE exactly as `lrdslam eval` (and TUM's evaluate_ate.py / evaluate_rpe.py) compute them.
Trajectories are TUM files or N x 8 arrays (t tx ty tz qx qy qz qw), e.g. System.trajectory()."""
from ._core import eval as _eval

ate = _eval.ate
rpe = _eval.rpe
improvement = _eval.improvement

__all__ = ["ate", "rpe", "improvement"]
