"""The new-environment guide (``docs/new_env.md``) stays true: its worked example
(``examples/integrator_env.py``) verifies, the guide's code is the example's code, and the
figures it prints are the ones a campaign prints."""

from __future__ import annotations

import doctest
import json
import re
import sys
import textwrap
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

from vlb_gym.cli import main
from vlb_gym.envs.modules import import_env_module
from vlb_gym.verify import CampaignConfig, run_campaign

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "integrator_env.py"
EXAMPLE_BEHAVIOR = ROOT / "examples" / "integrator_reach.json"
EXAMPLE_ID = "VLB-Integrator-v0"
GUIDE = ROOT / "docs" / "new_env.md"
COMMAND = ("$ vlb verify VLB-Integrator-v0 --env-module examples/integrator_env.py "
           "--behavior examples/integrator_reach.json --episodes 100 --epsilon 0.05")


def import_example() -> ModuleType:
    """Import ``examples/integrator_env.py`` as ``--env-module`` does (registering
    VLB-Integrator-v0): module ``integrator_env``, the name the guide's ``import`` gives."""
    return import_env_module(str(EXAMPLE))


def blocks(kind: str, numbered: bool = False) -> list[Any]:
    """The guide's fenced code blocks of one kind (python, json, console or pycon); with
    ``numbered``, (line number of the block's first line, block) pairs."""
    text = GUIDE.read_text()
    found = re.finditer(rf"^```{kind}\n(.*?)^```$", text, flags=re.MULTILINE | re.DOTALL)
    return [(text.count("\n", 0, m.start(1)), m[1]) if numbered else m[1] for m in found]


def test_example_behavior_verifies():
    import_example()
    report = run_campaign(CampaignConfig(EXAMPLE_ID, str(EXAMPLE_BEHAVIOR), 100, epsilon=0.05))
    assert (report["successes"], report["failures"]) == (100, 0)
    assert report["confidence"] == pytest.approx(1 - 0.95 ** 100, rel=1e-12)
    assert report["lower_bound"] == pytest.approx(0.05 ** (1 / 100), rel=1e-12)


def test_guide_python_excerpts_are_verbatim_in_the_example():
    source = EXAMPLE.read_text()
    excerpts = blocks("python")
    assert len(excerpts) >= 8
    for excerpt in excerpts:  # methods may be shown dedented
        code = textwrap.dedent(excerpt)
        assert any(textwrap.indent(code, pad) in source for pad in ("", "    ")), excerpt


def test_guide_shows_the_behavior_file():
    (shown,) = blocks("json")
    assert json.loads(shown) == json.loads(EXAMPLE_BEHAVIOR.read_text())


def test_guide_sessions_run_as_shown(monkeypatch):
    """The guide's ``>>>`` sessions, run as doctests from the repository root."""
    import_example()
    monkeypatch.chdir(ROOT)
    monkeypatch.setattr(sys, "path", list(sys.path))  # the session prepends examples/
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    names: dict = {}  # one session: each block sees the names of those before it
    for line, block in blocks("pycon", numbered=True):
        test = doctest.DocTestParser().get_doctest(block, names, "new_env.md", str(GUIDE), line)
        runner.run(test, clear_globs=False)
        names = test.globs
    result = runner.summarize(verbose=False)
    assert result.attempted >= 10 and result.failed == 0


def test_guide_command_prints_what_a_campaign_prints(monkeypatch):
    import_example()
    monkeypatch.chdir(ROOT)
    (session,) = [block for block in blocks("console") if "vlb verify" in block]
    command, *shown = session.rstrip("\n").splitlines()
    assert command == COMMAND
    config = CampaignConfig(EXAMPLE_ID, "examples/integrator_reach.json", 100, epsilon=0.05)
    printed = run_campaign(config).summary().splitlines()
    timing = re.compile(r"\d+\.\d s, \d+ episodes/s")
    assert [timing.sub("", line) for line in shown] == [timing.sub("", line) for line in printed]


def test_example_stays_short():
    assert len(EXAMPLE.read_text().splitlines()) < 200


def test_vlb_verifies_the_example_with_env_module(capsys, tmp_path):
    args = ["verify", EXAMPLE_ID, "--env-module", str(EXAMPLE), "--behavior", str(EXAMPLE_BEHAVIOR),
            "--episodes", "40", "--epsilon", "0.05", "--report", str(tmp_path / "r.json")]
    assert main(args) == 0
    assert main([*args[:-2], "--workers", "2", "--quiet"]) == 0  # workers import the module too
    assert "successes 40/40" in capsys.readouterr().out
    report = json.loads((tmp_path / "r.json").read_text())
    assert report["env_modules"] == [str(EXAMPLE)] and report["successes"] == 40


@pytest.mark.parametrize("module, message", [
    (None, "an env of your own needs --env-module"),
    ("/nonexistent/env.py", "--env-module /nonexistent/env.py: FileNotFoundError"),
    ("no_such_module_xyz", "--env-module no_such_module_xyz: ModuleNotFoundError"),
])
def test_env_module_errors_are_one_line(module, message, capsys):
    flags = ["--env-module", module] if module else []
    assert main(["verify", "VLB-Nowhere-v0", *flags, "--behavior", str(EXAMPLE_BEHAVIOR),
                 "--episodes", "3", "--epsilon", "0.1"]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


@pytest.mark.timeout(120)
def test_workers_that_cannot_build_the_campaign_fail_instead_of_respawning():
    """Registered in this process only (no env_modules): each worker's set-up fails, and the
    campaign raises that error instead of restarting workers forever."""
    import_example()
    config = CampaignConfig(EXAMPLE_ID, str(EXAMPLE_BEHAVIOR), 8, epsilon=0.05)
    with pytest.raises(Exception, match="VLB-Integrator"):
        run_campaign(config, workers=2)
