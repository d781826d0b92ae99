"""The natural-language behavior generalizer (the paper's Algorithm 1)."""
