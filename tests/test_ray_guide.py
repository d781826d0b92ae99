"""docs/ray.md's "Try it on one machine": its commands run as written, with free ports and short
temporary folders substituted, a home of their own (Ray writes its token to ~/.ray), and
``ray stop`` (which stops every Ray process of the machine) replaced by stopping these nodes.
A driver without the token is refused in one line first."""

from __future__ import annotations

import contextlib
import os
import re
import shlex
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

pytest.importorskip("ray")
pytestmark = [pytest.mark.ray, pytest.mark.xdist_group("ray"), pytest.mark.timeout(240)]

ROOT = Path(__file__).resolve().parent.parent
RAY = Path(sys.executable).parent / "ray"


def guide_commands() -> list[str]:
    text = (ROOT / "docs" / "ray.md").read_text()
    section = text.split("## Try it on one machine", 1)[1].split("\n## ", 1)[0]
    block = section.split("```console", 1)[1].split("```", 1)[0]
    return [line[2:] for line in block.splitlines() if line.startswith("$ ")]


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def stop(node: subprocess.Popen) -> None:
    """Stop a ``ray start --block`` node and everything it started (its own session)."""
    for sig, wait in ((signal.SIGTERM, 3), (signal.SIGKILL, 5)):
        try:
            os.killpg(node.pid, sig)
        except ProcessLookupError:
            return
        try:
            node.wait(wait)
            time.sleep(1)  # its children exit after it
        except subprocess.TimeoutExpired:
            continue
    with contextlib.suppress(ProcessLookupError):
        os.killpg(node.pid, signal.SIGKILL)  # stragglers of the group


def test_the_guide_on_one_machine(tmp_path):
    commands = guide_commands()
    assert "export RAY_AUTH_MODE=token" in commands and commands[-1] == "ray stop"
    folder = Path(tempfile.mkdtemp(prefix="vg", dir="/tmp"))  # AF_UNIX paths are short
    substitutions = {"6379": str(free_port()), "10001": str(free_port()),
                     "/tmp/ray-head": str(folder / "h"), "/tmp/ray-node1": str(folder / "n")}
    env = {**os.environ, "HOME": str(tmp_path), "PYTHONPATH": str(ROOT)}
    for name in ("RAY_ADDRESS", "RAY_AUTH_TOKEN", "RAY_AUTH_TOKEN_PATH", "RAY_AUTH_MODE"):
        env.pop(name, None)
    nodes: list[subprocess.Popen] = []
    runs: list[subprocess.CompletedProcess] = []
    try:
        for command in commands[:-1]:
            for old, new in substitutions.items():
                command = re.sub(rf"(?<![\w/-]){re.escape(old)}(?![\w/-])", new, command)
            words = [w for w in shlex.split(command) if w != ">/dev/null"]
            if words[0] == "export":
                name, _, value = words[1].partition("=")
                env[name] = value
            elif words[:2] == ["ray", "get-auth-token"]:
                subprocess.run([str(RAY), *words[1:]], env=env, capture_output=True,
                               timeout=60, check=True)
            elif words[0] == "ray":
                nodes.append(subprocess.Popen([str(RAY), *words[1:], "--block"], env=env,
                                              stdout=subprocess.DEVNULL,
                                              stderr=subprocess.DEVNULL,
                                              start_new_session=True))
                if len(nodes) == 1:
                    wait_for_port(int(substitutions["6379"]))
                else:
                    wait_for_nodes(len(nodes), env, substitutions["6379"])
            else:
                assert words[0] == "vlb"
                cli = [sys.executable, "-m", "vlb_gym.cli", *words[1:], "--quiet"]
                unset = {k: v for k, v in env.items() if k != "RAY_AUTH_MODE"}
                refused = subprocess.run(cli, env=unset, capture_output=True, text=True,
                                         timeout=60, check=False)
                runs.append(subprocess.run(cli, env=env, capture_output=True, text=True,
                                           timeout=120, check=False))
    finally:
        for node in reversed(nodes):
            stop(node)
        shutil.rmtree(folder, ignore_errors=True)
    assert refused.returncode == 2 and len(refused.stderr.splitlines()) == 1, refused.stderr
    assert "refused this process: it uses token authentication" in refused.stderr
    (run,) = runs
    assert run.returncode == 0, run.stderr
    assert "2000 episodes" in run.stdout and "successes 2000/2000" in run.stdout


def wait_for_port(port: int, tries: int = 400) -> None:
    """Until the head's GCS listens (a try every 0.3 s)."""
    for _ in range(tries):
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            return
        except OSError:
            time.sleep(0.3)
    pytest.fail(f"nothing listens on port {port}")


def wait_for_nodes(count: int, env: dict[str, str], port: str, tries: int = 120) -> None:
    """Until the cluster has ``count`` live nodes (asked through a small driver, which looks
    every 0.5 s, ``tries`` times)."""
    probe = ("import ray, sys, time\n"
             f"ray.init(address='127.0.0.1:{port}', logging_level='ERROR')\n"
             f"for _ in range({tries}):\n"
             f"    if sum(n['Alive'] for n in ray.nodes()) >= {count}:\n"
             "        sys.exit(0)\n"
             "    time.sleep(0.5)\n"
             "sys.exit('nodes did not join')\n")
    done = None
    for _ in range(tries // 2):  # the head's GCS is not listening at once
        done = subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True,
                              text=True, timeout=300, check=False)
        if done.returncode == 0:
            return
        time.sleep(1)
    pytest.fail(done.stderr[-2000:])
