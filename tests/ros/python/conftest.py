"""The ROS tests reuse the CLI helper of tests/python."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "python"))
