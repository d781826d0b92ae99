"""Every printed probability is on the side that claims less: a scan of every writer's output
(``vlb verify``'s summary and JSON statement, the report folder's markdown and HTML, the RL
comparison's table, ``vlb compare``) against the exact values it prints."""

from __future__ import annotations

import json
import re
from decimal import ROUND_CEILING, ROUND_FLOOR, ROUND_HALF_EVEN, Decimal

import pytest

from vlb_gym.cli import main

GRID = "VLB-GridExplore-v0"
NOISY = ["--env-kwarg", "action_noise=1.0"]  # about 1.7% of episodes fail
# a number that may render a probability: not a time (a node's mean step, "0.55 ms", which
# once read as the confidence 0.548 rounded up) nor a percentage
TOKEN = re.compile(r"(?<![\d.])-?\d\.\d{2,}(?![\d.])(?!\s*(?:ms|s|%)\b)(?!%)")


def renderings(value: float, digits: int) -> set[str]:
    exact = Decimal(repr(value))
    step = Decimal(1).scaleb(-digits)
    return {str(exact.quantize(step, rounding=r))
            for r in (ROUND_FLOOR, ROUND_CEILING, ROUND_HALF_EVEN)}


def check(text: str, lows: list[float], highs: list[float]) -> int:
    """Assert that every token of ``text`` that renders one of ``lows`` (``highs``) is at most
    (at least) it; the number of tokens that rendered one and could have gone either way."""
    telling = 0
    for token in TOKEN.findall(text):
        digits = len(token.split(".")[1])
        for value, low in [(v, True) for v in lows] + [(v, False) for v in highs]:
            if token not in renderings(value, digits):
                continue
            if low:
                assert Decimal(token) <= Decimal(repr(value)), (token, value)
            else:
                assert Decimal(token) >= Decimal(repr(value)), (token, value)
            telling += len(renderings(value, digits)) > 1
    return telling


@pytest.fixture
def campaign(tmp_path, capsys):
    """A fixed-N campaign with a few failures: its folder, store, report and summary."""
    store, report = tmp_path / "c.db", tmp_path / "r.json"
    assert main(["verify", GRID, "--behavior", "find_goal_and_oscillate", "--episodes", "400",
                 "--epsilon", "0.02", *NOISY, "--store", str(store), "--report", str(report),
                 "--quiet", "--workers", "2"]) == 0
    return tmp_path, capsys.readouterr().out, store, report


def test_vlb_verify_and_its_report_folder(campaign, capsys):
    folder, summary, store, report_path = campaign
    report = json.loads(report_path.read_text())
    assert 0 < report["failures"] < 20
    lows = [report["confidence"], report["lower_bound"]]
    assert check(summary, lows, []) >= 2
    assert check(report["statement"], lows, []) >= 2
    assert main(["report", str(store), "--out", str(folder / "out"), "--no-frames"]) == 0
    capsys.readouterr()
    for name in ("report.md", "report.html"):
        assert check((folder / "out" / name).read_text(), lows, []) >= 2


def test_a_sequential_campaign(capsys, tmp_path):
    assert main(["verify", GRID, "--behavior", "find_goal_and_oscillate", "--sequential",
                 "--epsilon", "0.05", *NOISY, "--report", str(tmp_path / "r.json"),
                 "--quiet"]) == 0
    summary = capsys.readouterr().out
    report = json.loads((tmp_path / "r.json").read_text())
    lows, highs = [report["lower_bound"], report["confidence"]], [report["upper_bound"]]
    assert check(summary, lows, highs) >= 1
    assert check(report["statement"], lows, highs) >= 1


def test_the_rl_comparison_table(campaign):
    from vlb_gym.baselines.compare import Row, markdown

    _, _, _, report_path = campaign
    report = json.loads(report_path.read_text())
    row = Row("find_goal", "noisy", "graph", None, report["episodes"], report["successes"],
              report["lower_bound"], report["confidence"], 59, 19.0, None, None, None, 1.0,
              tuple(e["index"] for e in report["failed_episodes"]))
    rate = report["successes"] / report["episodes"]
    assert check(markdown([row], report["episodes"], 0),
                 [report["lower_bound"], report["confidence"], rate], []) >= 1


def test_vlb_compare(capsys, tmp_path):
    for method in (["--pairs", "300"], ["--sequential", "--max-pairs", "600"]):
        out = tmp_path / "c.json"
        assert main(["compare", GRID, "find_goal_and_oscillate", "find_goal_and_oscillate",
                     "--b-env-kwarg", "action_noise=1.0", "--margin", "0.03", *method,
                     "--report", str(out), "--quiet"]) == 0
        summary = capsys.readouterr().out
        report = json.loads(out.read_text())
        low, high = report["interval"]
        highs = [high] + ([report["p_value"]] if "p_value" in report else [])
        assert check(summary, [low], highs) >= 1
