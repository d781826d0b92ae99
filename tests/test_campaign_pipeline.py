"""The campaign pipeline end to end: policy loaders, backends giving the same report, the JSONL
export, replays checked against the store, and report folders written from a store."""

from __future__ import annotations

import json
import shutil
import sqlite3

import gymnasium as gym
import numpy as np
import pytest

from vlb_gym.cli import main
from vlb_gym.verify import Campaign, CampaignConfig, PolicyRef, register_policy_loader
from vlb_gym.verify.episode import EpisodeResult
from vlb_gym.verify.export import EpisodesExport, read_export
from vlb_gym.verify.policies import policy_loader

from .conftest import EXAMPLES

GRID = "VLB-GridExplore-v0"
# how a run went, not what it found
RUN = ("wall_seconds", "episodes_per_second", "workers", "backend", "machine")


def found(report: dict) -> dict:
    return {k: v for k, v in report.items() if k not in RUN}


def verify(tmp_path, name: str, *extra: str) -> dict:
    out = tmp_path / f"{name}.json"
    assert main(["verify", GRID, "--behavior", "find_goal_and_oscillate", "--env-kwarg",
                 "action_noise=2.3", "--episodes", "40", "--epsilon", "0.1", "--seed", "3",
                 "--quiet", "--report", str(out), *extra]) == 0
    return json.loads(out.read_text())


@pytest.mark.ray
@pytest.mark.xdist_group("ray")
@pytest.mark.timeout(180)
def test_every_backend_gives_the_serial_report(tmp_path, capsys):
    pytest.importorskip("ray")
    serial = verify(tmp_path, "serial", "--backend", "serial")
    assert 0 < serial["failures"] < 40 and serial["backend"] == "serial"
    process = verify(tmp_path, "process", "--backend", "process", "--workers", "2")
    ray = verify(tmp_path, "ray", "--backend", "ray", "--workers", "2",
                 "--store", str(tmp_path / "ray.db"))
    assert found(process) == found(serial)
    assert found(ray) == found(serial) and ray["backend"] == "ray"


def test_ray_address_needs_the_ray_backend(capsys):
    assert main(["verify", GRID, "--behavior", "explore_until_goal", "--episodes", "3",
                 "--epsilon", "0.1", "--ray-address", "auto"]) == 2
    assert "--ray-address needs --backend ray" in capsys.readouterr().err


def test_policy_kinds_come_from_their_packages():
    from vlb_gym.baselines.train import SB3Loader
    from vlb_gym.core.library import BehaviorLoader

    assert isinstance(policy_loader("behavior"), BehaviorLoader)
    assert isinstance(policy_loader("sb3"), SB3Loader)
    with pytest.raises(ValueError, match=r"unknown policy kind 'nope' \(known: behavior, "
                                         r"random, sb3, sb3_sampled"):
        policy_loader("nope")


class SenseForever:
    """A policy of a kind of its own: sense where the robot stands, three times, then finish."""

    def reset(self, seed=None):
        self.left = 3

    def predict(self, observation, state=None, episode_start=None, deterministic=True):
        import numpy as np

        if not self.left:
            return None, None
        self.left -= 1
        return np.array([0, *np.floor(observation["position"] + 5).astype(int)]), "here"


class SenseLoader:
    runs_code = False

    def load(self, ref, env):
        return SenseForever()

    def files(self, ref, policy):
        return []

    def content(self, ref, policy):
        return {"sha256": "0" * 64}

    def trained_env(self, ref):
        return None


def test_a_registered_policy_kind_runs_like_any_other():
    register_policy_loader("sense-3", SenseLoader())
    with Campaign(CampaignConfig(GRID, PolicyRef("sense-3", "x"), 5)) as campaign:
        report = campaign.run(backend="serial")
        assert campaign.plan.to_dict()["policy"] == {"kind": "sense-3", "ref": "x",
                                                     "library": None}
    assert report["successes"] == 5 and report["mean_primitives"] == 3
    assert report.replay_command(0, 1) is None  # 'vlb replay' has no option for this kind


def test_the_export_has_a_header_and_a_closing_line(tmp_path):
    path = tmp_path / "e.jsonl"
    records = [EpisodeResult(i, 10 + i, 1, True, 2, 0, None, 0.1) for i in range(3)]
    with Campaign(CampaignConfig(GRID, "explore_until_goal", 5)) as campaign:
        plan = campaign.plan
    export = EpisodesExport(path, plan)
    for record in records:
        export.add(record)
    assert read_export(path) == (plan, records, None)  # killed: no closing line
    export.close(complete=False)
    assert read_export(path)[2] == {"complete": False, "episodes": 3}
    with pytest.raises(FileExistsError):
        EpisodesExport(path, {})


@pytest.fixture
def stored(tmp_path):
    """A campaign of a copied behavior file with failures, kept in a store."""
    behavior = tmp_path / "fixed_cell.json"
    shutil.copy(EXAMPLES / "fixed_cell.json", behavior)
    store = tmp_path / "campaign.db"
    assert main(["verify", GRID, "--behavior", str(behavior), "--episodes", "30", "--epsilon",
                 "0.1", "--quiet", "--store", str(store)]) == 0
    return store, behavior


def failed_index(store) -> int:
    with sqlite3.connect(store) as db:
        rows = db.execute("SELECT idx, record FROM episodes ORDER BY idx").fetchall()
    return next(i for i, record in rows if json.loads(record)["rho"] < 0)


def test_replay_from_the_store_checks_the_record(stored, tmp_path, capsys):
    store, behavior = stored
    capsys.readouterr()
    k = failed_index(store)
    assert main(["replay", str(store), "--episode", str(k)]) == 0
    out = capsys.readouterr().out
    assert "FAIL navigate" in out and f"episode {k} (seed" in out
    assert "reproduces the stored record" in out
    gif = tmp_path / "replay.gif"
    assert main(["replay", str(store), "--episode", str(k), "--render", str(gif)]) == 0
    assert gif.read_bytes().startswith(b"GIF8")
    # a record that the episode does not reproduce
    with sqlite3.connect(store) as db:
        (record,) = db.execute("SELECT record FROM episodes WHERE idx = ?", (k,)).fetchone()
        db.execute("UPDATE episodes SET record = ? WHERE idx = ?",
                   (json.dumps({**json.loads(record), "primitives": 99}), k))
    capsys.readouterr()
    assert main(["replay", str(store), "--episode", str(k)]) == 1
    assert "does NOT reproduce the stored record (differs in: primitives)" in \
        capsys.readouterr().err


def test_replay_refuses_what_it_cannot_replay(stored, capsys):
    store, behavior = stored
    capsys.readouterr()
    assert main(["replay", str(store), "--episode", "30"]) == 2
    assert "episode 30 is not stored (30 of 30 episodes are" in capsys.readouterr().err
    assert main(["replay", str(store), "--episode", "0", "--seed", "4"]) == 2
    assert "takes the campaign from the store" in capsys.readouterr().err
    behavior.write_text(behavior.read_text().replace("(4, 4)", "(4, 5)").replace(
        '"[4, 4]"', '"[4, 5]"').replace("4, 4", "4, 5"))
    assert main(["replay", str(store), "--episode", "0"]) == 2
    assert "changed since the campaign" in capsys.readouterr().err


def test_report_folder_from_a_store(stored, tmp_path, capsys):
    store, _ = stored
    out = tmp_path / "report"
    assert main(["report", str(store), "--out", str(out)]) == 0
    assert {p.name for p in out.iterdir()} >= {"report.json", "report.md", "report.html",
                                                "figures"}
    markdown = (out / "report.md").read_text()
    assert f"vlb replay {store} --episode" in markdown
    assert "failed episode" in markdown and "successful episode" in markdown  # frames
    # the grid's frames come with a legend of its colours and the cells' indices on the edges
    assert (out / "figures" / "frames-legend.png").is_file()
    assert "What the colours show" in markdown and "goal, sensed" in markdown
    assert "(the last: where it ended)" in markdown
    frame = plt_image(out / "figures" / "frames-0-0.png")
    assert frame.shape[0] == frame.shape[1] == 260  # drawn with its axes, not a bare thumbnail
    report = json.loads((out / "report.json").read_text())
    capsys.readouterr()
    assert main(["report", str(store), "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == report
    (tmp_path / "file").write_text("x")
    assert main(["report", str(store), "--out", str(tmp_path / "file")]) == 2


class ResetInfo(gym.Wrapper):
    """Reports ``info`` at the reset (the same object each time), and appends to its list
    at every step: what a record keeps is the start as the reset reported it."""

    def __init__(self, env, info):
        super().__init__(env)
        self.info = info

    def reset(self, **kwargs):
        obs, _ = self.env.reset(**kwargs)
        return obs, self.info

    def step(self, action):
        if isinstance(self.info.get("k"), list):
            self.info["k"].append(len(self.info["k"]))
        return self.env.step(action)


def _episode(info):
    from vlb_gym.core.library import load_behavior
    from vlb_gym.verify.episode import run_episode
    from vlb_gym.wrappers import RobustnessWrapper

    env = RobustnessWrapper(ResetInfo(gym.make(GRID), info))
    return run_episode(env, load_behavior("find_goal_and_oscillate", env), seed=3)


def test_the_record_keeps_the_start_as_the_reset_reported_it():
    result = _episode({"k": [0]})
    assert result.primitives > 1 and result.start == {"k": [0]}


def test_a_reset_info_that_cannot_be_recorded_fails_the_episode_not_the_campaign():
    import numpy as np

    result = _episode({"x": np.array(2.0)})  # a 0-d array: no JSON list
    assert result.rho == -1 and result.reason.startswith("TypeError") and result.error


def plt_image(path):
    """A PNG file as an array (matplotlib's reader)."""
    from matplotlib.image import imread

    return imread(path)


def test_report_folder_says_what_it_is_doing_while_it_works(stored, tmp_path, capsys):
    store, _ = stored
    assert main(["report", str(store), "--out", str(tmp_path / "out")]) == 0
    printed = capsys.readouterr()
    assert printed.err.splitlines() == [
        "vlb report: replaying 2 episode(s) for their frames ...",
        "vlb report: drawing the report of 30 episode(s) ..."]
    assert printed.out.startswith("wrote ")


def test_the_failed_step_is_drawn_on_the_last_frame(stored):
    """The replayed failed episode's last frame outlines, in the legend's colour, the cell its
    failed step was sent to, and nothing else does; a successful episode shows no such cell."""
    from vlb_gym.envs.grid_explore.viewer import CELL_PX, FAILED
    from vlb_gym.verify.replay import episode_frames
    from vlb_gym.verify.store import open_readonly

    reader = open_readonly(stored[0])
    try:
        plan, episodes = reader.plan(), reader.results()
    finally:
        reader.close()
    frames, key, why_not = episode_frames(plan, episodes)
    assert why_not is None and ("cell a failed step was sent to", FAILED) in key.colours
    failed = next(e for e in episodes if not e.success)
    step = failed.steps[-1]
    assert step["certificate"] is False  # a campaign stops at the first failed step
    images = frames[f"failed episode {failed.index}"]
    marked = [np.argwhere((image == FAILED).all(-1)) for image in images]
    assert all(len(m) == 0 for m in marked[:-1]) and len(marked[-1]) > 0
    i, j = step["param"]
    rows, cols = marked[-1][:, 0], marked[-1][:, 1]
    top, left = (key.cells - 1 - j) * CELL_PX, i * CELL_PX
    assert rows.min() >= top and rows.max() < top + CELL_PX
    assert cols.min() >= left and cols.max() < left + CELL_PX
    success = next(label for label in frames if label.startswith("successful"))
    assert not any((image == FAILED).all(-1).any() for image in frames[success])
