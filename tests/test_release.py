"""A release that installs: the wheel built from the tracked files holds the package's data
(shipped behaviors, schema, prompts, worked examples, assets), its version is the package's
one, and its dependencies are the core install's."""

from __future__ import annotations

import email
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import vlb_gym

ROOT = Path(__file__).resolve().parent.parent


def test_the_wheel_holds_the_package_and_its_data(tmp_path):
    tracked = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True,
                             check=True).stdout.split()
    source = tmp_path / "src"
    for name in tracked:  # only what a clone has: nothing built or left over
        if name.startswith(("vlb_gym/", "pyproject.toml", "README.md")):
            (source / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / name, source / name)
    built = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps",
                            "--no-build-isolation", "-q", str(source), "-w", str(tmp_path)],
                           capture_output=True, text=True, timeout=600)
    assert built.returncode == 0, built.stderr
    (wheel,) = tmp_path.glob("vlb_gym-*.whl")
    names = set(zipfile.ZipFile(wheel).namelist())
    data = [n for n in tracked if n.startswith("vlb_gym/") and not n.endswith(".py")]
    assert data and set(data) <= names, set(data) - names  # every shipped data file
    assert {n for n in tracked if n.startswith("vlb_gym/") and n.endswith(".py")} <= names
    info = next(n for n in names if n.endswith(".dist-info/METADATA"))
    metadata = email.message_from_bytes(zipfile.ZipFile(wheel).read(info))
    assert metadata["Version"] == vlb_gym.__version__  # written in one place
    core = [r for r in metadata.get_all("Requires-Dist") if "extra ==" not in r]
    assert any(r.startswith("matplotlib") for r in core)
    assert "vlb = vlb_gym.cli:main" in zipfile.ZipFile(wheel).read(
        info.replace("METADATA", "entry_points.txt")).decode()
