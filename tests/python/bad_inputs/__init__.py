"""The bad-input corpus's cases by kind (test_bad_input_corpus.py runs them)."""
