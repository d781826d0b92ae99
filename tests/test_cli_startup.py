"""``vlb`` starts quickly, documents every option, and ``vlb behaviors`` finds a behavior's env."""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from collections.abc import Iterator

import pytest

from vlb_gym.cli import main, parser
from vlb_gym.verify.records import EpisodeResult

from .conftest import explore_doc

#: what no ``--help`` may import: the commands import these when they run
HEAVY = ("scipy", "mujoco", "torch", "stable_baselines3", "networkx", "pydantic", "httpx",
         "vlb_gym.envs", "vlb_gym.verify")

HELPS = [["--help"], ["--version"], ["verify", "--help"], ["plan", "--help"],
         ["replay", "--help"], ["render", "--help"], ["behaviors", "--help"],
         ["schema", "--help"], ["synthesize", "--help"], ["scoop-setup", "--help"],
         ["baseline", "--help"], ["baseline", "train", "--help"], ["bench", "--help"],
         ["bench", "compare", "--help"]]


def python(code: str) -> str:
    """Run ``code`` in a fresh interpreter (the tests' own imports would hide what it imports)."""
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout


def test_help_imports_nothing_heavy():
    code = f"""
import contextlib, io, sys
from vlb_gym.cli import main
for argv in {HELPS!r}:
    with contextlib.redirect_stdout(io.StringIO()):
        try:
            main(argv)
        except SystemExit as exc:
            assert exc.code == 0, (argv, exc.code)
print(*[h for h in {HEAVY!r} if any(m == h or m.startswith(h + ".") for m in sys.modules)])
"""
    assert python(code).split() == []


def test_import_registers_the_envs_and_names_stay_public():
    code = """
import sys
import gymnasium as gym
import vlb_gym
heavy = sorted(m for m in sys.modules if m.startswith(("scipy", "networkx", "pydantic")))
assert heavy == [], heavy
gym.make("VLB-GridExplore-v0").close()
from vlb_gym import *
from vlb_gym.core import *
assert issubclass(BehaviorSpecError, ValueError) and callable(load_behavior)
assert "scoop_repeatedly" in shipped_behaviors() and RobustnessWrapper and BehaviorPolicy
assert set(vlb_gym.__all__) <= set(dir(vlb_gym))
print(ENV_IDS, __version__)
"""
    assert "VLB-Scoop-v0" in python(code)
    python('import gymnasium as gym; gym.make("vlb_gym:VLB-GridExplore-v0").close()')


def test_a_grid_campaign_leaves_the_slow_scipy_modules_alone():
    """scipy.signal (0.4 s: it brings scipy.stats) is imported by the plain navigate alone,
    scipy.stats by the bounds of a campaign with failures alone."""
    pytest.importorskip("numba")  # without it, the plain navigate needs scipy.signal
    code = """
import sys
from vlb_gym.verify.campaign import CampaignConfig, run_campaign
report = run_campaign(CampaignConfig("VLB-GridExplore-v0", "find_goal_and_oscillate", 20))
assert report["successes"] == 20, report["successes"]
print(*sorted(m for m in ("scipy.signal", "scipy.stats") if m in sys.modules))
"""
    assert python(code).split() == []


def test_a_campaign_imports_the_envs_preload_where_its_episodes_run():
    """The grid's compiled controller (0.3 s to import) is imported in this process only for an
    in-process campaign, and before its clock starts (its time and episodes/s are the
    episodes' own); a campaign on workers leaves it to them (their forkserver imports it)."""
    pytest.importorskip("numba")
    code = """
import sys, time
from vlb_gym.verify import campaign, engine
module = "vlb_gym.envs.grid_explore.compiled"
seen = []

class Clock:  # engine.time, recording whether the module was there when the clock started
    @staticmethod
    def perf_counter():
        seen.append(module in sys.modules)
        return time.perf_counter()

engine.time = Clock
config = campaign.CampaignConfig("VLB-GridExplore-v0", "find_goal_and_oscillate", 4)
with campaign.Campaign(config) as prepared:
    assert prepared.env.unwrapped.preload == (module,)
    assert prepared.run(workers=2)["successes"] == 4
    print(module in sys.modules, seen[0])
    seen.clear()
    assert prepared.run(workers=1)["successes"] == 4
    print(module in sys.modules, seen[0])
"""
    assert python(code).split() == ["False", "False", "True", "True"]


def test_verify_with_workers_starts_the_forkserver_first(tmp_path):
    """``vlb verify --workers 2`` starts the forkserver before its own imports (they run side by
    side), and the campaign's records are those of one worker."""
    code = f"""
import json, sys
from multiprocessing import forkserver
from vlb_gym.cli import main
from vlb_gym.verify import backends
started = []
real = backends.start_forkserver
backends.start_forkserver = lambda preload: (started.append(
    ("vlb_gym.verify.campaign" in sys.modules, list(preload))), real(preload))
for workers in ("2", "1"):  # the first run imports the campaign modules
    assert main(["verify", "VLB-GridExplore-v0", "--behavior", "find_goal_and_oscillate",
                 "--episodes", "12", "--epsilon", "0.05", "--workers", workers, "--quiet",
                 "--episodes-out", r"{tmp_path}/" + workers + ".jsonl"]) == 0
print(json.dumps(started))
"""
    assert json.loads(python(code).splitlines()[-1]) == [[False, ["vlb_gym.verify.campaign"]]]
    one, two = ([json.loads(line) for line in (tmp_path / f"{n}.jsonl").read_text().splitlines()]
                for n in (1, 2))
    strip = lambda records: sorted(  # noqa: E731
        (r["index"], r["rho"], r["seed"], EpisodeResult.from_dict(r).outcome()["steps"])
        for r in records if "index" in r)
    assert strip(one) == strip(two) and len(strip(one)) == 12


def test_lazy_packages_serve_names_and_submodules():
    code = """
import sys
import vlb_gym.verify as verify
assert "vlb_gym.verify.campaign" not in sys.modules
assert verify.min_episodes(0.05, 0.95) == 59 and verify.bounds.min_episodes is verify.min_episodes
assert verify.campaign.run_campaign is verify.run_campaign  # a submodule, imported on use
assert set(verify.__all__) <= set(dir(verify))
for name in ("nothing", "_private"):
    try:
        getattr(verify, name)
    except AttributeError as exc:
        assert name in str(exc)
    else:
        raise AssertionError(name)
print("ok")
"""
    assert python(code).split() == ["ok"]


def test_plan_imports_the_bounds_alone():
    code = """
import contextlib, io, sys
from vlb_gym.cli import main
with contextlib.redirect_stdout(io.StringIO()) as out:
    main(["plan", "--epsilon", "0.05", "--confidence", "0.95"])
assert "59" in out.getvalue(), out.getvalue()
print(*[m for m in ("networkx", "pydantic", "scipy.special", "vlb_gym.verify.campaign")
        if m in sys.modules])
"""
    assert python(code).split() == []


def actions(p: argparse.ArgumentParser) -> Iterator[tuple[argparse.ArgumentParser,
                                                          argparse.Action]]:
    """Every argument of ``p`` and of its subcommands, recursively."""
    for action in p._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                yield from actions(sub)
        elif not isinstance(action, (argparse._HelpAction, argparse._VersionAction)):
            yield p, action


def test_every_argument_has_help_that_states_its_default():
    checked = 0
    for p, action in actions(parser()):
        name = f"{p.prog} {'/'.join(action.option_strings) or action.metavar or action.dest}"
        assert action.help and action.help.strip(), f"{name}: no help"
        default = action.default
        text = p._get_formatter()._expand_help(action)
        assert text.count("default") <= 1 + action.help.count("default") - \
            action.help.count("(default"), f"{name}: {text}"  # stated once
        if action.nargs == 0:
            assert "(default: " not in text, f"{name}: {text}"  # a flag's default is its absence
            continue
        if default is None or default is False or default == []:
            continue
        shown = default if isinstance(default, (list, tuple)) else [default]
        assert "(default: " in text and all(str(v) in text for v in shown), f"{name}: {text}"
        checked += 1
    assert checked > 20


def test_help_states_no_empty_defaults(capsys):
    for argv in (["verify", "--help"], ["synthesize", "--help"], ["report", "--help"],
                 ["bench", "compare", "--help"]):
        with pytest.raises(SystemExit):
            main(argv)
        out = capsys.readouterr().out
        assert "default: None" not in out and "default: False" not in out
        assert "default: []" not in out and "default: True" not in out
        assert "AgentSpec(" not in out  # defaults as they would be typed


def test_behaviors_takes_the_env_from_the_behavior(capsys):
    pytest.importorskip("vlb_gym.envs.scoop.gl")  # MuJoCo, its headless backend chosen first
    assert main(["behaviors", "scoop_repeatedly"]) == 0
    assert "node scoop: primitive scoop [start] [terminal]" in capsys.readouterr().out


def test_behaviors_env_overrides_and_is_checked(write_behavior, capsys):
    doc = explore_doc()
    del doc["env"]
    path = write_behavior(doc)
    assert main(["behaviors", str(path), "--env", "VLB-GridExplore-v0"]) == 0
    assert "node sense: primitive sense [start] [terminal]" in capsys.readouterr().out
    assert main(["behaviors", "explore_until_goal", "--env", "VLB-Scoop-v0"]) == 2
    assert "written for 'VLB-GridExplore-v0', not 'VLB-Scoop-v0'" in capsys.readouterr().err


def test_behavior_without_env_needs_env_option(write_behavior):
    doc = explore_doc()
    del doc["env"]
    path = write_behavior(doc)
    proc = subprocess.run([sys.executable, "-m", "vlb_gym.cli", "behaviors", str(path)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.startswith("vlb behaviors: error: ") and proc.stderr.count("\n") == 1
    assert "--env" in proc.stderr


def test_behaviors_json_prints_the_file(capsys):
    assert main(["behaviors", "explore_until_goal", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["env"] == "VLB-GridExplore-v0"
