"""Every console session of the tutorials is run, so the pages cannot rot.

A ``console`` block of a page is a session: each ``$ vlb ...`` (or ``$ python ...``) line runs
(the installed ``vlb``, in a scratch directory holding the repository's ``examples``, with an
empty home; the commands of one page share it, in order, as a reader's would), and the lines
the page shows after a command must appear in its output (standard output and error
together), in order. A line ``...`` stands for lines left out, ``...`` within a line for the
rest of it; wall times and rates are not compared. A command whose output starts with ``^C``
is interrupted once it has run a while; any other exits 0, or 2 where it shows an ``error:``. A block right after ``<!-- session: not run: REASON
-->`` is not run, and says why in the page's source.
"""

from __future__ import annotations

import contextlib
import os
import re
import shlex
import shutil
import signal
import sqlite3
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PAGES = ["README.md", "docs/verify.md", "docs/behaviors.md", "docs/compare.md", "docs/envs.md",
         "docs/synthesis.md", "docs/rl.md", "docs/scoop.md", "docs/benchmarks.md"]
ELSEWHERE = {"docs/new_env.md": "tests/test_new_env_guide.py",  # its sessions, step by step
             "docs/ray.md": "tests/test_ray_guide.py"}  # on a local cluster of its own
BLOCK = re.compile(r"(<!-- session: not run: [^>]+ -->\n)?```console\n(.*?)```", re.S)
VOLATILE = [(re.compile(r"\b\d+(\.\d+)? s\b"), "T s"),
            (re.compile(r"\b\d+(\.\d+)? (episodes|pairs)/s\b"), r"R \2/s"),
            (re.compile(r"(resuming \S+): \d+ of"), r"\1: K of")]
VLB = Path(sys.executable).with_name("vlb")


@dataclass
class Command:
    line: str
    expected: list[str]

    @property
    def interrupted(self) -> bool:
        return bool(self.expected) and self.expected[0].startswith("^C")


def sessions(page: str) -> tuple[list[Command], int]:
    """The commands of ``page``'s sessions that run, and how many blocks it marks not run."""
    commands: list[Command] = []
    skipped = 0
    for marked, body in BLOCK.findall((ROOT / page).read_text()):
        if marked:
            skipped += 1
            continue
        for line in body.splitlines():
            if line.startswith("$ "):
                commands.append(Command(line[2:], []))
            elif commands:
                commands[-1].expected.append(line)
    return commands, skipped


def normalized(line: str) -> str:
    for pattern, replacement in VOLATILE:
        line = pattern.sub(replacement, line)
    return line.rstrip()


def matches(expected: str, line: str) -> bool:
    parts = [re.escape(part) for part in normalized(expected).split("...")]
    return re.fullmatch(".*".join(parts), normalized(line)) is not None


def run(command: Command, cwd: Path) -> tuple[int, str]:
    words = shlex.split(command.line, comments=True)
    programs = {"vlb": str(VLB), "python": sys.executable}
    assert words[0] in programs, f"a session runs vlb or python: {command.line}"
    argv = [programs[words[0]], *words[1:]]
    env = {k: v for k, v in os.environ.items() if k not in ("VLB_BEHAVIOR_DIR", "XDG_DATA_HOME")}
    env.update(HOME=str(cwd / "home"), COLUMNS="100")  # a reader's library: empty, theirs
    if not command.interrupted:
        done = subprocess.run(argv, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              text=True, timeout=600, env=env)
        return done.returncode, done.stdout.replace(env["HOME"], "~")
    process = subprocess.Popen(argv, cwd=cwd, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, env=env,
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    # (Ctrl-C as a terminal delivers it: a suite run in the background has SIGINT ignored, and
    # the ignoring is inherited)
    store = cwd / words[words.index("--store") + 1]
    deadline = time.monotonic() + 120
    while stored(store) < 50 and time.monotonic() < deadline:  # some, far from all
        time.sleep(0.05)
    process.send_signal(signal.SIGINT)
    out, _ = process.communicate(timeout=120)
    return 0, "^C" + out


SCRATCH = {"examples", "benchmarks", "vlb_gym", "home"}  # what the test put there itself


def unignored(scratch: Path) -> list[str]:
    """What the commands wrote in ``scratch`` that the repository would not ignore (where a
    reader runs them: in a clone)."""
    names = sorted(p.name + ("/" if p.is_dir() else "") for p in scratch.iterdir()
                   if p.name not in SCRATCH)
    if not names or not (ROOT / ".git").exists():
        return []
    done = subprocess.run(["git", "-C", str(ROOT), "check-ignore", "--no-index", *names],
                          capture_output=True, text=True)
    return sorted(set(names) - set(done.stdout.split()))


def stored(store: Path) -> int:
    """How many episodes ``store`` holds so far (0 before its table exists)."""
    try:
        with contextlib.closing(sqlite3.connect(f"file:{store}?mode=ro", uri=True)) as db:
            return db.execute("SELECT COUNT(*) FROM episodes").fetchone()[0]
    except sqlite3.Error:
        return 0


def check(command: Command, code: int, output: str) -> None:
    failing = any("error:" in line for line in command.expected)
    assert (code == 2) if failing else (code == 0), f"$ {command.line}\nexit {code}:\n{output}"
    lines = output.splitlines()
    at = 0
    for expected in command.expected:
        if expected.strip() == "...":
            continue
        found = next((i for i in range(at, len(lines)) if matches(expected, lines[i])), None)
        assert found is not None, (f"$ {command.line}\nshows the line\n{expected}\nwhich its "
                                   f"output lacks (after line {at}):\n{output}")
        at = found + 1


@pytest.mark.timeout(900)
@pytest.mark.parametrize("page", PAGES)
def test_every_session_of_the_page_runs_as_shown(page, tmp_path):
    commands, _ = sessions(page)
    shutil.copytree(ROOT / "examples", tmp_path / "examples")  # copies: paths show as given
    for shipped in ("benchmarks", "vlb_gym"):  # vlb_gym: the paper's scripted replies
        (tmp_path / shipped).symlink_to(ROOT / shipped)  # (the package itself: no shadow)
    for command in commands:
        check(command, *run(command, tmp_path))
    assert unignored(tmp_path) == [], "what the page's commands write must be git-ignored"


PYTHON = re.compile(r"```python\n(.*?)```", re.S)


@pytest.mark.timeout(600)
def test_every_example_of_the_python_page_runs(tmp_path):
    """Each code block of the page runs as a script of its own (it prints; nothing raises)."""
    blocks = PYTHON.findall((ROOT / "docs" / "python.md").read_text())
    assert len(blocks) >= 3
    for number, block in enumerate(blocks):
        script = tmp_path / f"example_{number}.py"
        script.write_text(block)
        done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, text=True,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=300,
                              env={**os.environ, "HOME": str(tmp_path / "home")})
        assert done.returncode == 0 and done.stdout.strip(), f"{block}\n{done.stdout}"
        script.unlink()
    assert unignored(tmp_path) == [], "what the page's examples write must be git-ignored"


def test_the_sessions_run_are_most_of_them():
    """Blocks are marked not run only where they need what the suite lacks: a language model,
    a network service, or minutes of training or simulation."""
    with_sessions = {str(p.relative_to(ROOT)) for p in [ROOT / "README.md",
                                                         *(ROOT / "docs").glob("*.md")]
                     if "```console" in p.read_text()}
    assert with_sessions <= set(PAGES) | set(ELSEWHERE), with_sessions - set(PAGES)
    ran = skipped = 0
    for page in PAGES:
        commands, marked = sessions(page)
        ran, skipped = ran + len(commands), skipped + marked
    assert ran >= 20 and skipped <= 13, (ran, skipped)
