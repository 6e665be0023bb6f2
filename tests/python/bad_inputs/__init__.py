"""The bad-input corpus's cases by kind (test_bad_input_corpus.py runs them)."""
from bad_inputs import images, lists, models, settings  # importing a kind registers its cases
from bad_inputs.registry import CASES, Ctx, huge_grey_png

__all__ = ["CASES", "Ctx", "huge_grey_png", "images", "lists", "models", "settings"]
