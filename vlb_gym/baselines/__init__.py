"""Stable-Baselines3 baselines, verified like behavior graphs (extra ``rl``).

Nothing here is specific to one environment except :mod:`.configs`.
"""
