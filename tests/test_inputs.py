"""A campaign's inputs travel with it (:mod:`vlb_gym.verify.inputs`): worker processes build
from the driver's bytes and check what they built against the plan (the Ray side:
tests/test_ray_cluster.py)."""

from __future__ import annotations

import dataclasses
import json
import shutil
from pathlib import Path

import pytest

from vlb_gym.core.files import InputFileError, read_limited, shipped
from vlb_gym.verify.campaign import Campaign, CampaignConfig
from vlb_gym.verify.inputs import InputsDiffer

ROOT = Path(__file__).resolve().parent.parent
GRID = "VLB-GridExplore-v0"
OTHER = ROOT / "vlb_gym" / "behaviors" / "find_goal_and_oscillate.json"


def records(results) -> list[dict]:
    return sorted((r.outcome() for r in results), key=lambda r: r["index"])


def test_workers_build_from_the_plan_not_the_disk(tmp_path, monkeypatch):
    """A library named only in the driver's environment, its file changed after the plan."""
    library = tmp_path / "library"
    library.mkdir()
    shutil.copy(ROOT / "examples" / "fixed_cell.json", library / "my_fixed.json")
    monkeypatch.setenv("VLB_BEHAVIOR_DIR", str(library))
    config = CampaignConfig(GRID, "my_fixed", 60)
    with Campaign(config) as campaign:
        expected = records(campaign.episodes(backend="serial"))
        assert any(not r["rho"] > 0 for r in expected)
        (library / "my_fixed.json").write_text(OTHER.read_text())
        monkeypatch.delenv("VLB_BEHAVIOR_DIR")
        assert records(campaign.episodes(workers=2, backend="process")) == expected


def test_a_worker_that_sees_another_behavior_refuses(tmp_path):
    behavior = tmp_path / "b.json"
    shutil.copy(ROOT / "examples" / "fixed_cell.json", behavior)
    with Campaign(CampaignConfig(GRID, str(behavior), 50)) as campaign:
        files = {**campaign.inputs.files, str(behavior.resolve()): OTHER.read_bytes()}
        campaign.inputs = dataclasses.replace(campaign.inputs, files=files)
        with pytest.raises(InputsDiffer, match="content digest .* not the plan's"):
            campaign.run(2, backend="process")


def test_a_worker_with_other_versions_refuses():
    with Campaign(CampaignConfig(GRID, "find_goal_and_oscillate", 20)) as campaign:
        versions = {**campaign.inputs.versions, "numpy": "0.0"}
        campaign.inputs = dataclasses.replace(campaign.inputs, versions=versions)
        with pytest.raises(InputsDiffer, match="numpy"):
            campaign.run(2, backend="process")


def test_the_plan_is_what_workers_check():
    with Campaign(CampaignConfig(GRID, "find_goal_and_oscillate", 5)) as campaign:
        assert campaign.inputs.content_sha256 == campaign.plan.content_sha256
        assert json.dumps(campaign.plan.versions) == json.dumps(dict(campaign.inputs.versions))


def test_shipped_files_are_the_only_files(tmp_path):
    here, elsewhere = tmp_path / "a.json", tmp_path / "b.json"
    here.write_text("{}")
    elsewhere.write_text("[]")
    with shipped({str(here.resolve()): b'{"x": 1}'}):
        assert read_limited(here) == b'{"x": 1}'
        with pytest.raises(InputFileError, match="not among the files shipped"):
            read_limited(elsewhere)
    assert read_limited(here) == b"{}"


def test_env_module_files_travel(tmp_path):
    """An --env-module file edited after the plan: workers import the driver's bytes."""
    module = tmp_path / "integrator_env.py"
    shutil.copy(ROOT / "examples" / "integrator_env.py", module)
    config = CampaignConfig("VLB-Integrator-v0", str(ROOT / "examples" / "integrator_reach.json"),
                            30, env_modules=(str(module),))
    with Campaign(config) as campaign:
        expected = records(campaign.episodes(backend="serial"))
        module.write_text("raise RuntimeError('edited after the plan')\n")
        assert records(campaign.episodes(workers=2, backend="process")) == expected


def _parent_of(child_ref: str) -> dict:
    return {"name": "parent", "description": "a sub-behavior, then stop", "env": GRID,
            "nodes": [{"id": "child", "behavior": child_ref}], "start": {"node": "child"},
            "terminals": ["child"]}


@pytest.mark.parametrize("through", ["a symlinked folder", "a symlinked library file"])
def test_workers_without_the_users_links_reach_every_shipped_file(tmp_path, monkeypatch,
                                                                  through):
    """A sub-behavior reached through a link the driver has and a worker lacks (a Ray node):
    the worker reaches it as the driver's parent named it, and finds it shipped."""
    real, library, folder = tmp_path / "real", tmp_path / "library", tmp_path / "behaviors"
    for made in (real, library, folder):
        made.mkdir()
    shutil.copy(ROOT / "examples" / "fixed_cell.json", real / "child.json")
    if through == "a symlinked folder":
        (folder / "sub").symlink_to(real, target_is_directory=True)
        parent = _parent_of("sub/child.json")
        link = folder / "sub"
    else:
        (library / "my_child.json").symlink_to(real / "child.json")
        monkeypatch.setenv("VLB_BEHAVIOR_DIR", str(library))
        parent = _parent_of("my_child")
        link = library / "my_child.json"
    (folder / "parent.json").write_text(json.dumps(parent))
    with Campaign(CampaignConfig(GRID, str(folder / "parent.json"), 30)) as campaign:
        expected = records(campaign.episodes(backend="serial"))
        link.unlink()  # what a worker elsewhere sees: no link, and no file behind it
        shutil.rmtree(real)
        assert records(campaign.episodes(workers=2, backend="process")) == expected
