"""The layers: the envs, the core and the verifier import nothing from the layers above them
(the RL baselines, the synthesizer, the CLI), read from the source and seen at run time."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "vlb_gym"
LOWER = ("envs", "core", "verify")
UPPER = ("vlb_gym.baselines", "vlb_gym.abstractor", "vlb_gym.cli")


def imported_modules(path: Path) -> set[str]:
    """Every module ``path`` imports, relative imports resolved against its package."""
    package = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts[:-1])
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = package.split(".")[:len(package.split(".")) - node.level + 1] \
                if node.level else []
            module = ".".join([*base, *([node.module] if node.module else [])])
            found |= {module} | {f"{module}.{alias.name}" for alias in node.names}
    return found


@pytest.mark.parametrize("layer", LOWER)
def test_lower_layers_import_nothing_above_them(layer):
    offending = {f"{path.relative_to(PACKAGE.parent)}: {module}"
                 for path in (PACKAGE / layer).rglob("*.py")
                 for module in imported_modules(path)
                 if module.startswith(UPPER)}
    assert not offending, sorted(offending)


def test_the_import_scan_sees_relative_imports():
    path = PACKAGE / "envs" / "grid_explore" / "env.py"
    assert any(m.startswith("vlb_gym.envs.grid_explore.") for m in imported_modules(path))


def test_a_grid_campaign_runs_without_the_upper_layers():
    code = """
import sys
import gymnasium as gym
import vlb_gym
from vlb_gym.verify.campaign import CampaignConfig, run_campaign
gym.make("VLB-GridExplore-v0").reset(seed=0)
report = run_campaign(CampaignConfig("VLB-GridExplore-v0", "explore_until_goal", 5))
print(*sorted(m for m in sys.modules if m.startswith(%r)))
""" % (UPPER,)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == []


def test_no_import_circle_through_the_campaign_engine():
    """No module of the engine's path (campaign, comparison, engine, store, inputs, records,
    episode, policies) imports, even inside a function, one that imports it back."""
    import networkx as nx

    verify = PACKAGE / "verify"
    names = {path.stem for path in verify.glob("*.py")}
    graph = nx.DiGraph()
    for path in verify.glob("*.py"):
        for module in imported_modules(path):
            parts = module.split(".")
            if parts[:2] == ["vlb_gym", "verify"] and len(parts) > 2 and parts[2] in names:
                graph.add_edge(path.stem, parts[2])
    engine = {"campaign", "comparison", "engine", "store", "inputs", "records", "episode",
              "policies"}
    circles = [c for c in nx.simple_cycles(graph) if engine & set(c)]
    assert not circles, circles
