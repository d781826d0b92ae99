"""Shared fixtures: registered envs and a behavior runner."""

from __future__ import annotations

import json
from pathlib import Path

import gymnasium as gym
import pytest

import vlb_gym
from vlb_gym.wrappers import RobustnessWrapper

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def pytest_configure(config):
    """One torch thread per test process: the suite runs one process per core (-n 2 on 2
    cores), and torch's default of one thread per core in each made the agents' small networks
    wait on each other (a 30-pair comparison against an agent took 80 s instead of 24 s)."""
    try:
        import torch
    except ImportError:
        return
    torch.set_num_threads(1)


@pytest.fixture(autouse=True)
def user_library(tmp_path_factory, monkeypatch):
    """Every test gets an empty user behavior library, never the real one."""
    directory = tmp_path_factory.mktemp("library")
    monkeypatch.setenv("VLB_BEHAVIOR_DIR", str(directory))
    return directory


@pytest.fixture
def grid_env():
    env = RobustnessWrapper(gym.make("VLB-GridExplore-v0"))
    yield env
    env.close()


@pytest.fixture
def write_behavior(tmp_path):
    """Write a behavior document (dict or raw text) to a file and return its path."""

    def write(doc, name: str = "behavior.json") -> Path:
        path = tmp_path / name
        path.write_text(doc if isinstance(doc, str) else json.dumps(doc))
        return path

    return write


def explore_doc(**changes) -> dict:
    """A copy of the shipped explore_until_goal document with top-level fields replaced."""
    from importlib import resources

    doc = json.loads(resources.files("vlb_gym.behaviors").joinpath("explore_until_goal.json")
                     .read_text())
    doc.update(changes)
    return doc


__all__ = ["EXAMPLES", "explore_doc", "vlb_gym"]
