"""Campaigns on a real two-node local Ray cluster: a lost node, a cluster left without CPUs,
inputs that travel with the campaign and a worker that would build something else."""

from __future__ import annotations

import contextlib
import dataclasses
import logging
import os
import shutil
import signal
import tempfile
import time
from pathlib import Path

import pytest

from vlb_gym.verify.campaign import Campaign, CampaignConfig
from vlb_gym.verify.inputs import InputsDiffer
from vlb_gym.verify.ray_connect import ClusterError, RayOptions
from vlb_gym.verify.store import CampaignStore

ray = pytest.importorskip("ray")
from ray.cluster_utils import Cluster  # noqa: E402

pytestmark = [pytest.mark.ray, pytest.mark.xdist_group("ray"), pytest.mark.timeout(240)]

ROOT = Path(__file__).resolve().parent.parent
FAST_DEATH = {"health_check_period_ms": 500, "health_check_failure_threshold": 3,
              "health_check_initial_delay_ms": 0}  # a killed node is declared dead in ~2 s
GRID = "VLB-GridExplore-v0"
NOISY = {"action_noise": 1.0}  # some failures, so that records differ between episodes


@pytest.fixture(scope="module")
def cluster():
    """A head node without CPUs (so actors live on worker nodes only) and one worker node of
    one CPU; tests add and remove worker nodes."""
    if ray.is_initialized():
        pytest.skip("a Ray instance is running in this process")
    folder = tempfile.mkdtemp(prefix="vr", dir="/tmp")  # AF_UNIX paths are short
    cluster = Cluster(initialize_head=True, head_node_args={
        "num_cpus": 0, "temp_dir": folder, "include_dashboard": False,
        "_system_config": FAST_DEATH})
    cluster.add_node(num_cpus=1)
    ray.init(address=cluster.address, log_to_driver=False, logging_level=logging.ERROR)
    yield cluster
    ray.shutdown()
    cluster.shutdown()
    shutil.rmtree(folder, ignore_errors=True)


def records(results) -> list[dict]:
    return sorted((r.outcome() for r in results), key=lambda r: r["index"])


def clean(config: CampaignConfig) -> list[dict]:
    with Campaign(config) as campaign:
        return records(campaign.episodes(backend="serial"))


def kill_node(cluster, node) -> None:
    """The node gone as a machine goes: its Ray processes killed, its workers (which outlive
    their raylet for a while, answering their caller directly) too."""
    raylet = node.all_processes["raylet"][0].process.pid
    workers = [int(p.name) for p in Path("/proc").iterdir() if p.name.isdigit()
               and parent(p) == raylet]
    cluster.remove_node(node, allow_graceful=False)
    for pid in workers:
        with contextlib.suppress(ProcessLookupError):
            os.kill(pid, signal.SIGKILL)


def parent(process: Path) -> int | None:
    try:
        return int((process / "stat").read_text().rsplit(")", 1)[1].split()[1])
    except (OSError, IndexError, ValueError):
        return None


def lose_node_after(cluster, node, count: int, started=None):
    """An on_episode callback that kills ``node`` after ``count`` episodes, once ``started()``
    says an actor runs there (until then each episode waits a little, so that the campaign
    outlasts the actor's start)."""
    seen = []

    def on_episode(result) -> None:
        seen.append(result)
        if len(seen) < count or node not in cluster.worker_nodes:
            return
        if started is None or started():
            kill_node(cluster, node)
        else:
            time.sleep(0.03)
    return on_episode


def test_lost_node_reruns_its_episodes_elsewhere(cluster, caplog):
    config = CampaignConfig(GRID, "find_goal_and_oscillate", 300, env_kwargs=NOISY)
    doomed = cluster.add_node(num_cpus=1)
    cluster.wait_for_nodes()
    kept = []

    def started() -> bool:
        return any(doomed.node_id in m for m in caplog.messages)

    with caplog.at_level(logging.DEBUG, "vlb_gym.verify.ray"), Campaign(config) as campaign:
        on_episode = lose_node_after(cluster, doomed, 20, started)
        report = campaign.run(2, lambda r: (kept.append(r), on_episode(r)), backend="ray",
                              ray=RayOptions(stall=20))
    assert doomed not in cluster.worker_nodes
    assert any("lost a Ray node" in m for m in caplog.messages), "\n".join(caplog.messages)
    assert records(kept) == clean(config)
    with Campaign(config) as campaign:
        assert report["successes"] == campaign.run(1, backend="serial")["successes"]


def test_no_cpu_left_is_one_error_and_the_store_resumes(cluster, tmp_path):
    config = CampaignConfig(GRID, "find_goal_and_oscillate", 200, env_kwargs=NOISY)
    (only,) = cluster.worker_nodes
    store = CampaignStore(tmp_path / "c.db")
    try:
        with Campaign(config) as campaign, \
                pytest.raises(ClusterError, match="no Ray actor could start within 8 s"):
            campaign.run(1, lose_node_after(cluster, only, 30), store, "ray",
                         RayOptions(stall=8))  # a start takes seconds on a busy machine
        stored = len(store.done())
    finally:
        store.close()
    assert 30 <= stored < 200
    cluster.add_node(num_cpus=1)
    cluster.wait_for_nodes()
    kept = []
    store = CampaignStore(tmp_path / "c.db")
    try:
        with Campaign(config) as campaign:
            report = campaign.run(1, kept.append, store, "ray")
        assert records(store.results()) == clean(config)
    finally:
        store.close()
    assert len(kept) == 200 - stored and report["episodes"] == 200


def test_inputs_travel_with_the_campaign(cluster, tmp_path, monkeypatch):
    """A behavior file changed after the plan, and a library that only the driver's
    environment names: the actors build what the plan recorded."""
    library = tmp_path / "library"
    library.mkdir()
    shutil.copy(ROOT / "examples" / "fixed_cell.json", library / "my_fixed.json")
    monkeypatch.setenv("VLB_BEHAVIOR_DIR", str(library))
    config = CampaignConfig(GRID, "my_fixed", 120)
    expected = clean(config)
    assert any(not r["rho"] > 0 for r in expected)
    with Campaign(config) as campaign:
        (library / "my_fixed.json").write_text(
            (ROOT / "vlb_gym" / "behaviors" / "find_goal_and_oscillate.json").read_text())
        monkeypatch.delenv("VLB_BEHAVIOR_DIR")
        assert records(campaign.episodes(workers=1, backend="ray")) == expected


def test_an_actor_that_sees_another_behavior_refuses(cluster, tmp_path):
    behavior = tmp_path / "b.json"
    shutil.copy(ROOT / "examples" / "fixed_cell.json", behavior)
    other = (ROOT / "vlb_gym" / "behaviors" / "find_goal_and_oscillate.json").read_bytes()
    with Campaign(CampaignConfig(GRID, str(behavior), 50)) as campaign:
        files = {**campaign.inputs.files, str(behavior.resolve()): other}
        campaign.inputs = dataclasses.replace(campaign.inputs, files=files)
        with pytest.raises(InputsDiffer, match="content digest .* not the plan's"):
            campaign.run(1, backend="ray")


def test_comparison_on_the_cluster(cluster):
    from vlb_gym.verify.comparison import Comparison, ComparisonConfig

    config = ComparisonConfig(GRID, "find_goal_and_oscillate",
                              str(ROOT / "examples" / "fixed_cell.json"), 60)
    with Comparison(config) as comparison:
        on_ray, serial = (comparison.run(1, backend=b) for b in ("ray", "serial"))
    assert on_ray["counts"] == serial["counts"] and on_ray["counts"]["a_only"] > 0
    assert on_ray["discordant_pairs"] == serial["discordant_pairs"]
