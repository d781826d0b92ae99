"""``vlb verify/compare --backend ray`` when Ray cannot be reached or started: one line, exit
code 2, within the timeout (hang guards, not timings)."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
from pathlib import Path

import pytest

from vlb_gym.verify.ray_connect import RayOptions

pytest.importorskip("ray")
pytestmark = [pytest.mark.ray, pytest.mark.xdist_group("ray")]

ROOT = Path(__file__).resolve().parent.parent
VERIFY = ["verify", "VLB-GridExplore-v0", "--behavior", "find_goal_and_oscillate",
          "--episodes", "20", "--epsilon", "0.05", "--backend", "ray", "--quiet"]


def vlb(args: list[str], **env: str) -> subprocess.CompletedProcess:
    environment = {**os.environ, "PYTHONPATH": str(ROOT), **env}
    return subprocess.run([sys.executable, "-m", "vlb_gym.cli", *args], capture_output=True,
                          text=True, timeout=60, env=environment, check=False)


def closed_port() -> int:
    """A port of 127.0.0.1 that nothing listens on (free a moment ago)."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def one_error(done: subprocess.CompletedProcess, command: str = "verify") -> str:
    assert done.returncode == 2, done.stderr
    lines = done.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"vlb {command}: error: "), done.stderr
    assert done.stdout == ""
    return lines[0]


@pytest.mark.timeout(60)
@pytest.mark.parametrize("address", ["127.0.0.1:{port}", "ray://127.0.0.1:{port}"])
def test_nothing_listening_is_one_line(address):
    address = address.format(port=closed_port())
    line = one_error(vlb([*VERIFY, "--ray-address", address, "--ray-timeout", "10"]))
    assert f"cannot reach Ray at {address}: Connection refused" in line


@pytest.mark.timeout(60)
def test_unresolvable_host_is_one_line():
    line = one_error(vlb(["compare", "VLB-GridExplore-v0", "find_goal_and_oscillate",
                          "explore_until_goal", "--pairs", "10", "--backend", "ray",
                          "--ray-address", "no-such-host.invalid:6379", "--ray-timeout", "10",
                          "--quiet"]), "compare")
    assert "host 'no-such-host.invalid' does not resolve" in line


@pytest.mark.timeout(60)
def test_silent_port_ends_within_the_timeout():
    """Something accepts connections but never answers as Ray does."""
    with socket.socket() as server:
        server.bind(("127.0.0.1", 0))
        server.listen()
        port = server.getsockname()[1]
        done = vlb([*VERIFY, "--ray-address", f"127.0.0.1:{port}", "--ray-timeout", "3"])
    assert done.returncode == 2
    assert "no answer within 3 s (--ray-timeout)" in done.stderr.splitlines()[0]


@pytest.mark.timeout(90)
def test_ray_that_cannot_start_is_one_line(tmp_path):
    """A temporary folder whose socket paths exceed AF_UNIX's limit: Ray cannot start."""
    deep = tmp_path / ("d" * 100)
    deep.mkdir()
    line = one_error(vlb(VERIFY, TMPDIR=str(deep), RAY_ADDRESS="127.0.0.1:1"))
    assert "Ray could not start a local instance" in line


def test_options_are_checked():
    with pytest.raises(ValueError, match="timeout must be a positive"):
        RayOptions(timeout=0)
    done = vlb([*VERIFY[:-3], "--ray-address", "127.0.0.1:1"])
    assert "--ray-address needs --backend ray" in one_error(done)


@pytest.mark.timeout(240)
def test_ray_workers_import_nothing_from_the_folder_the_command_runs_in(tmp_path):
    """Ray puts the driver's folder first on its workers' import path unless the job has a
    working_dir: a networkx.py where a campaign runs must not be what its actors import."""
    for name in ("networkx", "pydantic", "scipy"):
        (tmp_path / f"{name}.py").write_text(
            f"open({str(tmp_path / ('HIT_' + name))!r}, 'w').close()\n"
            "raise ImportError('a hostile module of the working folder')\n")
    environment = {**os.environ, "PYTHONPATH": str(ROOT), "PYTHONSAFEPATH": "1"}  # the driver
    done = subprocess.run([sys.executable, "-m", "vlb_gym.cli", *VERIFY, "--workers", "1"],
                          capture_output=True, text=True, timeout=200, env=environment,
                          cwd=tmp_path, check=False)
    assert done.returncode == 0, done.stderr
    assert "successes 20/20" in done.stdout or "P[success]" in done.stdout, done.stdout
    assert not list(tmp_path.glob("HIT_*"))
