"""The ``vlb`` command line against bad input: output paths, env settings, input files, Ctrl-C,
worker counts, huge sample sizes and guarantees that never claim more than was computed."""

from __future__ import annotations

import json
import math
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from decimal import Decimal
from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.stats import binom, poisson

from vlb_gym.cli import common, main
from vlb_gym.envs.grid_explore import GridExploreEnv
from vlb_gym.core.text import bounded
from vlb_gym.verify import bounds
from vlb_gym.verify.campaign import Campaign, CampaignConfig
from vlb_gym.verify.report import Report
from vlb_gym.verify.episode import EpisodeResult
from vlb_gym.verify.export import read_export

from .test_bounds import exact_miss

from .conftest import EXAMPLES

SHIPPED = Path(__file__).resolve().parent.parent / "vlb_gym" / "behaviors"
GRID = "VLB-GridExplore-v0"


@pytest.fixture
def behavior(tmp_path) -> Path:
    """A user's behavior file (a copy of a shipped one)."""
    path = tmp_path / "mine.json"
    shutil.copy(SHIPPED / "explore_until_goal.json", path)
    return path


def verify(*extra: str, behavior: str | Path = "explore_until_goal", episodes: int = 3) -> int:
    return main(["verify", GRID, "--behavior", str(behavior), "--episodes", str(episodes),
                 "--epsilon", "0.1", "--quiet", *extra])


def one_line_error(capsys, *words: str) -> str:
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("vlb ") and "Traceback" not in err, err
    for word in words:
        assert word in err, err
    return err


# --------------------------------------------------------------------------- 1. output paths


@pytest.mark.parametrize("option", ["--report", "--episodes-out"])
def test_an_output_naming_the_behavior_file_is_refused(option, behavior, capsys):
    before = behavior.read_bytes()
    assert verify(option, str(behavior), behavior=behavior) == 2
    one_line_error(capsys, option, "is an input of this command")
    assert behavior.read_bytes() == before


def test_an_output_naming_the_behavior_file_through_another_path_is_refused(behavior, capsys):
    link = behavior.parent / "link.json"
    os.link(behavior, link)
    before = behavior.read_bytes()
    assert verify("--report", str(link), behavior=behavior) == 2
    one_line_error(capsys, "is an input of this command")
    assert behavior.read_bytes() == before


def test_an_existing_episodes_out_needs_force(tmp_path, capsys):
    stream = tmp_path / "episodes.jsonl"
    stream.write_text("precious\n")
    assert verify("--episodes-out", str(stream)) == 2
    one_line_error(capsys, "exists already", "--force")
    assert stream.read_text() == "precious\n"
    assert verify("--episodes-out", str(stream), "--force") == 0
    assert [r.index for r in read_export(stream)[1]] == [0, 1, 2]


def test_an_existing_report_is_replaced(tmp_path):
    report = tmp_path / "report.json"
    report.write_text("old\n")
    assert verify("--report", str(report)) == 0
    assert json.loads(report.read_text())["episodes"] == 3


@pytest.mark.parametrize("where, message", [
    (lambda tmp: tmp, "is a directory"),
    (lambda tmp: tmp / "file.txt" / "report.json", "is not a directory"),
    (lambda tmp: Path("/dev/null"), "not a regular file"),
])
def test_an_unusable_report_path_fails_before_the_campaign(where, message, tmp_path, capsys):
    (tmp_path / "file.txt").write_text("")
    stream = tmp_path / "episodes.jsonl"
    assert verify("--report", str(where(tmp_path)), "--episodes-out", str(stream),
                  episodes=100_000) == 2  # fails at once: no episode ran
    one_line_error(capsys, "--report", message)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file.txt"]  # no stream, no tmp file


@pytest.mark.skipif(os.geteuid() == 0, reason="root may write anywhere")
def test_an_unwritable_report_directory_fails_before_the_campaign(tmp_path, capsys):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o500)
    assert verify("--report", str(locked / "sub" / "report.json"), episodes=100_000) == 2
    one_line_error(capsys, "permission denied")


def test_report_and_episodes_out_must_differ(tmp_path, capsys):
    path = tmp_path / "out.json"
    assert verify("--report", str(path), "--episodes-out", str(path)) == 2
    one_line_error(capsys, "the same file")
    assert not path.exists()


def test_check_output():
    check = common.check_output
    assert check("new/dir/file.json", [], False, "--out") == Path("new/dir/file.json")
    with pytest.raises(common.UsageError, match="--out .*: is an input"):
        check(__file__, [None, Path(__file__)], True, "--out")
    with pytest.raises(common.UsageError, match="exists already"):
        check(__file__, [], False, "--out")


def test_render_out_is_checked_before_the_episode(behavior, tmp_path, capsys):
    before = behavior.read_bytes()
    assert main(["render", GRID, "--behavior", str(behavior), "--out", str(behavior)]) == 2
    one_line_error(capsys, "--out", "is an input")
    assert behavior.read_bytes() == before
    assert main(["render", GRID, "--behavior", str(behavior), "--out", str(tmp_path)]) == 2
    one_line_error(capsys, "is a directory")


def test_synthesize_out_may_not_overwrite_its_inputs(tmp_path, capsys):
    replies = tmp_path / "replies.json"
    shutil.copy(Path(__file__).resolve().parent.parent / "vlb_gym" / "abstractor" / "paper"
                / "behavior1.replies.json", replies)
    before = replies.read_bytes()
    assert main(["synthesize", GRID, "explore until a goal is found", "--scripted",
                 str(replies), "--out", str(replies), "--force"]) == 2
    one_line_error(capsys, "is an input")
    assert replies.read_bytes() == before


# --------------------------------------------------------------------------- 2. env settings


@pytest.mark.parametrize("kwarg, message", [
    ("n_obstacles=200", "do not fit"),
    ("n_goals=2.5", "n_goals must be an integer"),
    ("n_goals=true", "n_goals must be an integer"),
    ("action_noise=Infinity", "action_noise must be finite"),
    ("render_mode=human", "render_mode"),
    ("size=100000", "size must be >= 2 and <= 64"),
    ("max_episode_steps=0", "max_episode_steps must be a positive integer"),
    ("colour=3", "unexpected keyword argument 'colour'"),
])
def test_impossible_env_settings_are_usage_errors(kwarg, message, tmp_path, capsys):
    report = tmp_path / "report.json"
    assert verify("--env-kwarg", kwarg, "--report", str(report)) == 2
    err = one_line_error(capsys, message)
    assert "was raised from the environment creator" not in err
    assert not report.exists()


def test_only_vlb_environments_are_accepted(capsys):
    assert main(["verify", "CartPole-v1", "--behavior", "explore_until_goal", "--episodes", "3",
                 "--epsilon", "0.1"]) == 2
    one_line_error(capsys, "unknown environment 'CartPole-v1'", "VLB-GridExplore-v0")


@pytest.mark.parametrize("kwargs, error, message", [
    ({"size": 10.0}, TypeError, "size must be an integer"),
    ({"size": True}, TypeError, "size must be an integer"),
    ({"size": 65}, ValueError, "size must be >= 2 and <= 64"),
    ({"n_obstacles": -1}, ValueError, "n_obstacles must be >= 0"),
    ({"n_goals": 0}, ValueError, "n_goals must be >= 1"),
    ({"n_obstacles": 97, "n_goals": 3}, ValueError, "do not fit"),
    ({"action_noise": float("nan")}, ValueError, "action_noise must be finite"),
    ({"action_noise": 1e300}, ValueError, "action_noise must be >= 0.0 and <= 100.0"),
    ({"action_noise": "0.5"}, TypeError, "action_noise must be a number"),
])
def test_grid_constructor_checks_its_arguments(kwargs, error, message):
    with pytest.raises(error, match=message):
        GridExploreEnv(**kwargs)


def test_grid_too_crowded_to_sample_is_a_value_error():
    with pytest.raises(ValueError, match="too crowded"):
        GridExploreEnv(size=64, n_obstacles=4000, n_goals=1).reset(seed=0)


@pytest.mark.parametrize("kwargs, error, message", [
    ({"placement_noise": -0.01}, ValueError, "placement_noise"),
    ({"placement_noise": 0.5}, ValueError, "placement_noise must be >= 0.0 and <= 0.04"),
    ({"yaw_noise_deg": float("inf")}, ValueError, "yaw_noise_deg must be finite"),
    ({"grain_counts": 260}, TypeError, "grain_counts must be a non-empty list"),
    ({"grain_counts": []}, TypeError, "grain_counts must be a non-empty list"),
    ({"grain_counts": [260.5]}, TypeError, "grain_counts must be an integer"),
    ({"grain_counts": [100_000]}, ValueError, "grain_counts must be >= 1 and <= 350"),
    ({"delivered_threshold_g": float("nan")}, ValueError, "delivered_threshold_g"),
    ({"width": 4096}, ValueError, "width must be >= 1 and <= 640"),
    ({"height": 2.5}, TypeError, "height must be an integer"),
    ({"sleep_tolerance": 0.5}, ValueError, "sleep_tolerance must be >= 0.0 and <= 0.1"),
    ({"sleep_tolerance": "fast"}, TypeError, "sleep_tolerance"),
    ({"solver_iterations": 0}, ValueError, "solver_iterations must be >= 1 and <= 200"),
    ({"solver_iterations": 20.0}, TypeError, "solver_iterations must be an integer"),
    ({"solver_tolerance": 0.0}, ValueError, "solver_tolerance must be >= 1e-10 and <= 0.01"),
    ({"solver_tolerance": float("inf")}, ValueError, "solver_tolerance must be finite"),
    ({"solver_iterations": 10**9}, ValueError, "solver_iterations must be >= 1 and <= 200"),
    ({"solver_iterations": True}, TypeError, "solver_iterations must be an integer"),
    ({"solver_tolerance": "nan"}, TypeError, "solver_tolerance must be a number"),
])
def test_scoop_constructor_checks_its_arguments(kwargs, error, message):
    pytest.importorskip("vlb_gym.envs.scoop.gl")  # MuJoCo, its headless backend chosen first
    from vlb_gym.envs.scoop import ScoopEnv

    with pytest.raises(error, match=message):
        ScoopEnv(**kwargs)


# --------------------------------------------------------------------------- 3. input files


@pytest.mark.parametrize("scripted", ["/dev/null", "no-such-replies.json"])
def test_unreadable_scripted_replies_are_usage_errors(scripted, capsys):
    assert main(["synthesize", GRID, "explore", "--scripted", scripted]) == 2
    one_line_error(capsys, "vlb synthesize: error:", scripted)


def write_agent(tmp_path: Path, metadata: str | bytes | None) -> Path:
    agent = tmp_path / "agent.zip"
    agent.write_bytes(b"")
    if metadata is not None:
        meta = agent.with_suffix(".json")
        meta.write_bytes(metadata if isinstance(metadata, bytes) else metadata.encode())
    return agent


@pytest.mark.parametrize("metadata, message", [
    (None, "cannot read the agent's metadata"),
    ('{"algorithm": "ppo", "env_kwargs": {}}', "needs 'env_id'"),
    ('{"algorithm": "ppo", "env_id": "VLB-GridExplore-v0"}', "needs 'env_kwargs'"),
    ('{"algorithm": "ppo", "env_id": "x", "env_kwargs": []}', "needs 'env_kwargs'"),
    ('{"algorithm": "dqn", "env_id": "x", "env_kwargs": {}}', "unknown algorithm"),
    ('{"algorithm": "ppo", "env_id": "x", "env_kwargs": {}, "observation": "pixels"}',
     "observation must be one of flat, image, spatial, not 'pixels'"),
    ('{"algorithm": "ppo", "env_id": "x", "env_kwargs": {}, "observation": "spatial"}',
     "the spatial policy needs action masks"),
    ('["ppo"]', "not a JSON object"),
    ('{"algorithm": ', "not JSON"),
    ("[" * 1000 + "]" * 1000, "nested deeper"),
    (b" " * 2_000_000, "the limit is"),
])
def test_bad_agent_metadata_is_a_usage_error(metadata, message, tmp_path, capsys):
    agent = write_agent(tmp_path, metadata)
    assert main(["verify", GRID, "--policy", str(agent), "--episodes", "3",
                 "--epsilon", "0.1"]) == 2
    one_line_error(capsys, "agent.json", message)


def test_policy_help_warns_that_loading_runs_code(capsys):
    with pytest.raises(SystemExit):
        main(["verify", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert "Loading it runs code from the file (pickle): load only agents you trust" in out


# --------------------------------------------------------------------------- 4. Ctrl-C


@pytest.mark.timeout(60)
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP])
def test_ctrl_c_keeps_the_episodes_and_prints_one_line(signum, tmp_path):
    """Ctrl-C, and SIGTERM or SIGHUP to the process group (what `timeout`, a closed terminal or
    a job scheduler send), end a campaign alike: one line, every finished episode kept, the
    workers' temporary directory gone, exit code 128 + the signal (130 for Ctrl-C)."""
    stream = tmp_path / "episodes.jsonl"
    # the workers' temporary directory, watched; short, as the forkserver's socket lives there
    # (AF_UNIX paths are limited to 108 bytes)
    temporary = Path(tempfile.mkdtemp(prefix="vlbt", dir="/tmp"))
    proc = subprocess.Popen(
        [sys.executable, "-m", "vlb_gym.cli", "verify", GRID, "--behavior",
         "find_goal_and_oscillate", "--episodes", "100000", "--epsilon", "0.05", "--workers", "2",
         "--episodes-out", str(stream)], env={**os.environ, "TMPDIR": str(temporary)},
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        # a process group of its own, as a shell job has, with Ctrl-C's default handling even
        # when this test runs in the background (where SIGINT is ignored and that is inherited)
        start_new_session=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        deadline = time.monotonic() + 40
        while not (stream.exists() and stream.read_text().count('"record":"episode"') > 5):
            assert proc.poll() is None and time.monotonic() < deadline, proc.communicate()
            time.sleep(0.05)
        os.killpg(proc.pid, signum)  # SIGINT: what Ctrl-C in a terminal does
        out, err = proc.communicate(timeout=15)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    plan, episodes, end = read_export(stream)
    assert proc.returncode == 128 + signum, err
    left = [p for p in temporary.iterdir() if p.name.startswith("vlb-workers-")]
    shutil.rmtree(temporary, ignore_errors=True)
    assert not left
    assert "Traceback" not in err and err.count("\n") == 1, err
    assert err == f"vlb verify: interrupted; {len(episodes)} episode(s) written to {stream}\n"
    assert 0 < len(episodes) < 100000 and plan.episodes == 100000
    assert end == {"complete": False, "episodes": len(episodes)}
    assert all(r.rho == 1 for r in episodes)


def test_ctrl_c_in_any_command_is_one_line(monkeypatch, capsys):
    def interrupted(*args):
        raise KeyboardInterrupt

    monkeypatch.setattr(bounds, "min_episodes", interrupted)
    try:
        code = main(["plan", "--epsilon", "0.05", "--confidence", "0.95"])
    except KeyboardInterrupt:  # would end the test session
        pytest.fail("KeyboardInterrupt escaped main()")
    assert code == 130
    assert capsys.readouterr().err == "vlb plan: interrupted\n"


# --------------------------------------------------------------------------- 5. workers


@pytest.mark.parametrize("cpus, workers, episodes, expected, reason", [
    (2, 1000, 3, 2, "2 CPU(s) available"),
    (8, 4, 1, 1, "1 episode(s)"),
])
def test_workers_are_clamped_with_a_note(cpus, workers, episodes, expected, reason, tmp_path,
                                         monkeypatch, capsys):
    monkeypatch.setattr(common, "available_cpus", lambda: cpus)
    report = tmp_path / "report.json"
    assert verify("--workers", str(workers), "--report", str(report), episodes=episodes) == 0
    assert capsys.readouterr().err == (f"vlb verify: note: --workers {workers} reduced to "
                                       f"{expected} ({reason})\n")
    assert json.loads(report.read_text())["workers"] == expected


@pytest.mark.timeout(60)
@pytest.mark.parametrize("kind", ["truncated JSON", "fifo", "device"])
def test_a_bad_behavior_with_workers_is_one_line_and_leaves_no_process(kind, tmp_path):
    """``--workers 2`` starts the forkserver before the behavior is read: a file that fails
    (malformed, a FIFO that would block a reader, an endless device) still ends in one error
    line, at once, and the forkserver goes with the command."""
    path = {"truncated JSON": tmp_path / "bad.json", "fifo": tmp_path / "fifo.json",
            "device": Path("/dev/zero")}[kind]
    if kind == "truncated JSON":
        path.write_text('{"name": [')
    elif kind == "fifo":
        os.mkfifo(path)
    proc = subprocess.Popen(
        [sys.executable, "-m", "vlb_gym.cli", "verify", GRID, "--behavior", str(path),
         "--episodes", "100", "--epsilon", "0.05", "--workers", "2"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        _, err = proc.communicate(timeout=50)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith(f"vlb verify: error: {path}"), err
    deadline = time.monotonic() + 10  # its session: the command and the forkserver it started
    while time.monotonic() < deadline:
        try:
            os.killpg(proc.pid, 0)
        except ProcessLookupError:
            break
        time.sleep(0.1)
    else:
        pytest.fail("a process of the command outlived it by 10 s")


# --------------------------------------------------------------------------- 6. min_episodes


@pytest.mark.timeout(10)
@pytest.mark.parametrize("eps, conf, k", [(1e-30, 0.99, 0), (1e-19, 0.99, 1), (1e-12, 0.5, 7),
                                          (1e-300, 0.95, 0), (5e-324, 0.9, 0)])
def test_min_episodes_for_tiny_epsilon_is_quick_and_minimal(eps, conf, k):
    n = bounds.min_episodes(eps, conf, k)
    assert bounds.confidence(n, k, eps) >= conf > bounds.confidence(n - 1, k, eps)
    if k == 0:  # (1 - eps)**n <= 1 - conf: n = log(1 - conf) / log(1 - eps) ~ -log(1 - conf) / eps
        assert float(n * Fraction(eps) / Fraction(-math.log1p(-conf))) == pytest.approx(1, rel=1e-9)
    else:  # Binomial(n, eps) is Poisson(n * eps) up to O(eps)
        assert poisson.sf(k, n * eps) == pytest.approx(conf, rel=1e-9)


def test_plan_with_tiny_epsilon_returns(capsys):
    assert main(["plan", "--epsilon", "1e-30", "--confidence", "0.99", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["episodes"] == 4605170185988084757070680245862
    assert main(["plan", "--epsilon", "1e-19", "--confidence", "0.99", "--failures", "1"]) == 0
    n = int(capsys.readouterr().out.split()[0])  # conservative, and within a relative 1e-14
    allowed = 1 - Decimal(0.99)  # of the least N (floats' resolution), against 60 digits
    assert exact_miss(n, 1, 1e-19) <= allowed < exact_miss(n - n // 10 ** 14, 1, 1e-19)


def test_plan_past_the_float_range_is_a_usage_error(capsys):
    assert main(["plan", "--epsilon", "1e-320", "--confidence", "0.9", "--failures", "3"]) == 2
    one_line_error(capsys, "beyond floating point")


def exact_min_episodes(eps: float, conf: float) -> int:
    """Least n with (1 - eps)**n <= 1 - conf in exact rational arithmetic (no failures)."""
    survive, target, n = 1 - Fraction(eps), 1 - Fraction(conf), 1
    power = survive
    while power > target:
        power, n = power * survive, n + 1
    return n


@pytest.mark.parametrize("eps, conf", [(0.05, 0.95), (0.01, 0.99), (0.2, 0.999999),
                                       (0.003, 0.7), (0.5, 0.75)])
def test_min_episodes_without_failures_is_exact(eps, conf):
    assert bounds.min_episodes(eps, conf) == exact_min_episodes(eps, conf)


@settings(max_examples=60, deadline=None)
@given(eps=st.floats(1e-3, 0.6), conf=st.floats(0.01, 0.999), k=st.integers(0, 6))
def test_min_episodes_matches_a_linear_scan(eps, conf, k):
    n = bounds.min_episodes(eps, conf, k)
    scan = k + 1
    while bounds.confidence(scan, k, eps) < conf:
        scan += 1
    assert n == scan
    assert binom.sf(k, n, eps) >= conf * (1 - 1e-12)  # scipy agrees, independently


# --------------------------------------------------------------------------- 7. floor, not round


def test_floor_str_rounds_down():
    assert bounds.floor_str(0.9499958) == "0.94999"
    assert bounds.floor_str(1 - 0.95 ** 2000) == "0.99999"  # 1.0 in floating point
    assert bounds.floor_str(0.999995) == "0.99999"
    assert bounds.floor_str(0.99408) == "0.99408"
    assert bounds.floor_str(0.0) == "0.00000"
    assert bounds.one_minus_str(0.05) == "0.95"
    assert bounds.one_minus_str(1e-7) == "0.9999999"


def campaign_report(n: int, failures: int, epsilon: float = 0.05, delta: float = 0.05
                    ) -> Report:
    with Campaign(CampaignConfig(GRID, "explore_until_goal", n, epsilon, delta)) as campaign:
        plan = campaign.plan
    results = [EpisodeResult(i, i, -1 if i < failures else 1, True, 3, int(i < failures),
                             "x" if i < failures else None, 0.0) for i in range(n)]
    return Report.build(plan, results, 1.0, 1)


def test_printed_guarantees_never_claim_more_than_computed():
    report = campaign_report(1125, 44)
    assert report["lower_bound"] == pytest.approx(0.9499958, abs=1e-7)
    assert "P[success] >= 0.94999 at confidence level 0.95" in report["statement"]
    assert "P[success] >= 0.94999 at confidence level 0.95" in report.summary()
    report = campaign_report(2000, 0)
    assert "with confidence 0.99999" in report["statement"]
    assert "with confidence 0.99999" in report.summary()
    report = campaign_report(20, 0, epsilon=1e-7)
    assert "P[success] >= 0.9999999 with confidence" in report.summary()


def test_plan_prints_the_reached_confidence_rounded_down(capsys):
    assert main(["plan", "--epsilon", "0.05", "--confidence", "0.95"]) == 0
    out = capsys.readouterr().out  # 59 episodes reach 0.9515055
    assert out.startswith("59 episodes") and "(reached: 0.95150)" in out


# --------------------------------------------------------------------------- 9. user errors


@pytest.mark.parametrize("args", [
    ["verify", "CartPole-v1", "--behavior", "explore_until_goal", "--episodes", "3",
     "--epsilon", "0.1"],
    ["verify", GRID, "--behavior", "explore_until_goal", "--episodes", "3", "--epsilon", "0.1",
     "--env-kwarg", "size=100000"],
    ["verify", GRID, "--behavior", str(EXAMPLES / "nope.json"), "--episodes", "3",
     "--epsilon", "0.1"],
    ["verify", GRID, "--behavior", "explore_until_goal", "--episodes", "many", "--epsilon", "0.1"],
    ["synthesize", GRID, "explore", "--scripted", "/dev/null"],
    ["verify", GRID, "--policy", "no-such-agent.zip", "--episodes", "3", "--epsilon", "0.1"],
])
def test_user_errors_are_one_line_without_traceback(args):
    proc = subprocess.run([sys.executable, "-m", "vlb_gym.cli", *args], capture_output=True,
                          text=True, timeout=60)
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"vlb {args[0]}: error: ") and proc.stderr.count("\n") == 1, \
        proc.stderr
    assert "Traceback" not in proc.stderr


@pytest.mark.parametrize("argv", [
    ["synthesize", GRID, "explore", "--name", "../../x", "--scripted", "replies.json"],
    ["scoop-setup", "--name", "/tmp/elsewhere"],
    ["synthesize", GRID, "explore", "--name", "a" * 65, "--scripted", "replies.json"],
])
def test_a_behavior_name_that_is_a_path_is_refused_where_it_is_given(argv, capsys, tmp_path,
                                                                     monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    assert exit_.value.code == 2
    one_line_error(capsys, "--name", "is not a behavior name")
    assert list(tmp_path.iterdir()) == []  # nothing written anywhere


def test_an_episode_index_beyond_any_store_is_one_line(tmp_path, capsys):
    store = tmp_path / "s.db"
    assert verify("--store", str(store)) == 0
    capsys.readouterr()
    assert main(["replay", str(store), "--episode", str(2**70)]) == 2
    one_line_error(capsys, "episode", "not stored")


# --------------------------------------------------------------------------- the terminal


def test_nothing_printed_can_drive_the_terminal():
    from vlb_gym.cli.terminal import neutral

    hostile = "a\x1b]52;c;ZXZpbA==\x07b\x1b[2J\u202ec\x9b\x00d\te\nf\rg"
    shown = neutral(hostile)
    assert shown == "a\\x1b]52;c;ZXZpbA==\\x07b\\x1b[2J\\u202ec\\x9b\\x00d\te\nf\\rg"
    assert neutral("\r 40%|####") == "\r 40%|####"  # a progress bar redraws its line


@settings(max_examples=200, deadline=None)
@given(st.text())
def test_neutral_text_has_no_control_or_format_character(text):
    import unicodedata

    from vlb_gym.cli.terminal import neutral

    shown = neutral(text)
    assert "\r" not in shown[1:]
    for char in shown:
        assert char in "\t\n\r" or unicodedata.category(char) not in ("Cc",) and \
            char not in "\u200b\u200c\u200d\u200e\u200f\u202a\u202b\u202c\u202d\u202e" \
            "\u2066\u2067\u2068\u2069\ufeff"


def test_a_store_reason_is_printed_neutralised(tmp_path, capsys):
    import sqlite3

    store = tmp_path / "c.db"
    assert verify("--store", str(store), behavior=EXAMPLES / "fixed_cell.json",
                  episodes=12) == 0
    capsys.readouterr()
    with sqlite3.connect(store) as db:  # a store from elsewhere, its reasons edited
        for index, text in db.execute("SELECT idx, record FROM episodes").fetchall():
            record = json.loads(text)
            if record["reason"]:
                record["reason"] = "\x1b]0;owned\x07\x1b[2J" + record["reason"]
                db.execute("UPDATE episodes SET record = ? WHERE idx = ?",
                           (json.dumps(record), index))
    assert main(["report", str(store)]) == 0
    out = capsys.readouterr().out
    assert "\x1b" not in out and "\\x1b]0;owned\\x07\\x1b[2J" in out
    assert main(["report", str(store), "--out", str(tmp_path / "r"), "--no-frames"]) == 0
    written = (tmp_path / "r" / "report.md").read_text()  # a file a user may cat
    assert "\x1b" not in written and "\x07" not in written and "\\x1b" in written


def test_a_delta_too_small_for_floating_point_is_one_line(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["verify", GRID, "--behavior", "explore_until_goal", "--sequential",
              "--epsilon", "0.1", "--delta", "1e-300"])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "1 - 1e-300 is 1 in floating point" in err


def test_an_agent_zip_without_an_agent_is_one_line(tmp_path, capsys):
    import zipfile

    agent = tmp_path / "agent.zip"
    with zipfile.ZipFile(agent, "w") as archive:
        archive.writestr("readme.txt", "not an agent")
    agent.with_suffix(".json").write_text(json.dumps(
        {"algorithm": "maskable_ppo", "env_id": "VLB-GridExplore-FindGoal-v0",
         "env_kwargs": {}}))
    assert main(["verify", "VLB-GridExplore-FindGoal-v0", "--policy", str(agent),
                 "--episodes", "3", "--epsilon", "0.1"]) == 2
    one_line_error(capsys, "agent.zip: not a saved maskable_ppo agent")


def test_workers_never_import_the_files_where_a_campaign_runs(tmp_path):
    """A ``random.py`` and a ``signal.py`` in the folder a 2-worker campaign runs in are not
    imported by its workers (the forkserver started them with '' first on their path)."""
    marker = tmp_path / "imported"
    for name in ("random", "signal"):
        (tmp_path / f"{name}.py").write_text(
            f"open({str(marker)!r}, 'a').write('{name} ')\nraise SystemExit(3)\n")
    # as the `vlb` script starts: its own folder, not the current one, first on the path
    launcher = "import sys; sys.path.pop(0); from vlb_gym.cli import main; sys.exit(main())"
    proc = subprocess.run(
        [sys.executable, "-c", launcher, "verify", "VLB-GridExplore-v0", "--behavior",
         "explore_until_goal", "--episodes", "8", "--epsilon", "0.3", "--workers", "2"],
        cwd=tmp_path, capture_output=True, text=True, timeout=300,
        env={k: v for k, v in os.environ.items() if k != "PYTHONSAFEPATH"})
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "successes 8/8" in proc.stdout
    assert not marker.exists(), marker.read_text()


@pytest.mark.parametrize("command", [
    ["verify", "{X}", "--behavior", "explore_until_goal", "--episodes", "2", "--epsilon", "0.1"],
    ["compare", "{X}", "explore_until_goal", "explore_until_goal", "--pairs", "2"],
    ["synthesize", "{X}", "x", "--certify", "--promise", "goal_found()", "--yes"],
    ["behaviors", "{X}"], ["report", "{X}"], ["replay", "{X}", "--episode", "0"],
    ["verify", GRID, "--behavior", "explore_until_goal", "--episodes", "2", "--epsilon", "0.1",
     "--env-kwarg", "{X}=1"],
], ids=lambda c: c[0])
def test_a_megabyte_argument_is_echoed_shortened_in_one_line(command, capsys):
    huge = "A" * 1_000_000
    argv = [word.replace("{X}", huge) for word in command]
    try:
        code = main(argv)
    except SystemExit as stop:
        code = stop.code
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err[:300]
    assert len(err) < 3000 and "characters]" in err


@given(st.text(max_size=5000))
def test_bounded_keeps_short_messages_and_bounds_the_rest(message):
    shown = bounded(message)
    assert len(shown) <= 2200
    if len(message) <= 2000 and all(len(w) <= 160 for w in message.split(" ")):
        assert shown == message


@pytest.mark.parametrize("suffix", ["-wal", "-shm", ""])
def test_report_out_is_never_where_sqlite_keeps_the_store(tmp_path, capsys, suffix):
    store = tmp_path / "s.db"
    assert verify("--store", str(store), behavior=EXAMPLES / "fixed_cell.json",
                  episodes=4) == 0
    capsys.readouterr()
    assert main(["report", str(store), "--out", f"{store}{suffix}", "--no-frames"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "is an input of this command" in err
    assert not Path(f"{store}{suffix}").is_dir()
    assert main(["report", str(store)]) == 0  # the store still opens


# errors of the package's own making that are not about the user's input: outcomes of an
# episode (a controller, an IK or a perception failure fail that episode), a picture a report
# goes without, a worker's traceback carried home, and private signals of one module
NOT_USER_ERRORS = {"PerceptionFailure", "IKFailure", "ControllerFailure", "PictureUnavailable",
                   "RemoteTraceback", "_Failed", "_Failure"}


def test_every_error_about_what_the_user_gave_is_a_user_error():
    """One hierarchy: every exception class vlb-gym defines is a UserError (the CLI's one line
    and exit 2; a library caller's one except clause) unless it is listed as something else."""
    import importlib
    import inspect
    import pkgutil

    import vlb_gym
    from vlb_gym import UserError

    defined = {}
    for module in pkgutil.walk_packages(vlb_gym.__path__, "vlb_gym."):
        if module.name.endswith("__main__"):  # runs the command line
            continue
        loaded = importlib.import_module(module.name)
        for name, value in vars(loaded).items():
            if inspect.isclass(value) and issubclass(value, BaseException) \
                    and value.__module__ == loaded.__name__:
                defined[name] = value
    assert NOT_USER_ERRORS <= set(defined)
    users = {n for n, c in defined.items() if issubclass(c, UserError)}
    assert users | NOT_USER_ERRORS == set(defined), set(defined) - users - NOT_USER_ERRORS
    assert {"BehaviorSpecError", "InputFileError", "StoreError", "UsageError", "EnvSetupError",
            "ClusterError"} <= users


def test_running_out_of_memory_ends_a_command_in_one_line(monkeypatch, capsys):
    from vlb_gym.cli import verify as verify_command

    def exhausted(args):
        raise MemoryError

    monkeypatch.setattr(verify_command, "cmd_plan", exhausted)
    assert main(["plan", "--epsilon", "0.05", "--confidence", "0.99"]) == 2
    err = capsys.readouterr().err
    assert err == "vlb plan: error: out of memory (what this command was given needs more " \
        "memory than it may use here)\n"
