"""Environments of vlb-gym; each registers itself on ``import vlb_gym``."""
