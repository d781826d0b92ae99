"""vlb scoop-setup: words (through a real chat server) or typed commands move the arm; the saved
pose becomes a scoop_repeatedly copy in the library."""

from __future__ import annotations

import ast
import io
import json

import gymnasium as gym
import numpy as np
import pytest

from vlb_gym.envs.scoop.setup import (ScoopSetup, SetupError, Translate, parse_command,
                                      parse_reply)
from vlb_gym.cli import main
from vlb_gym.core.library import BehaviorLibrary
from vlb_gym.envs.scoop.env import DEFAULT_SENSING_POSE

from .chat_server import ChatServer


def saved_pose(library_dir, name):
    doc = json.loads((library_dir / f"{name}.json").read_text())
    return np.array(ast.literal_eval(doc["variables"]["sensing_pose"]))


def test_typed_commands_without_a_model(monkeypatch, tmp_path, user_library, capsys):
    monkeypatch.setattr("sys.stdin", io.StringIO(
        "translate 0 0 0.05\nrotate 0 0 5\nfly away\nsave\nquit\n"))
    assert main(["scoop-setup", "--name", "typed", "--images", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "unknown command" in out and "both containers in view" in out
    pose = saved_pose(user_library, "typed")
    expected = np.array(DEFAULT_SENSING_POSE) + [0, 0, 0.05, 0, 0, np.radians(5)]
    assert np.allclose(pose, expected, atol=1e-3)
    assert len(list(tmp_path.glob("wrist_view_*.png"))) == 3
    assert "typed" in BehaviorLibrary(user_library).names()


def test_words_through_a_chat_server(monkeypatch, tmp_path, user_library, capsys):
    replies = [("reply", "import os; os.system('x')"),  # not data: rejected, sent back
               ("reply", json.dumps({"calls": [{"helper": "translate", "dy": -0.05},
                                               {"helper": "save"}]}))]
    with ChatServer(replies) as server:
        monkeypatch.setattr("sys.stdin", io.StringIO("5 cm to the right, then keep it\n"))
        assert main(["scoop-setup", "--name", "spoken", "--images", str(tmp_path),
                     "--base-url", server.url, "--model", "m", "--retries", "0"]) == 0
    assert "not a valid list of helper calls" in server.requests[1]["messages"][-1]["content"]
    assert np.allclose(saved_pose(user_library, "spoken")[:3],
                       np.array(DEFAULT_SENSING_POSE[:3]) + [0, -0.05, 0], atol=1e-3)
    transcript = json.loads((tmp_path / "transcript.json").read_text())
    assert transcript["exchanges"][0]["error"] and transcript["saved"]


@pytest.mark.parametrize("reply, message", [
    ('{"calls": [{"helper": "exec", "code": "1"}]}', "does not match any of the expected tags"),
    ('{"calls": [{"helper": "translate", "dx": 5}]}', "less than or equal to 0.3"),
    ('{"calls": [{"helper": "save", "extra": 1}]}', "Extra inputs are not permitted"),
    ("sure, moving now", "Invalid JSON"),
])
def test_replies_are_data_checked_against_a_schema(reply, message):
    with pytest.raises(SetupError, match=message):
        parse_reply(reply)


def test_commands_parse_and_check():
    assert parse_command("translate 0.01 0 -0.02") == [Translate(helper="translate", dx=0.01,
                                                                 dz=-0.02)]
    with pytest.raises(SetupError, match="takes 3 number"):
        parse_command("rotate 5")


def test_unreachable_moves_leave_the_pose_alone(tmp_path):
    env = gym.make("VLB-Scoop-v0").unwrapped
    env.reset(seed=0)
    session = ScoopSetup(env, tmp_path)
    with pytest.raises(SetupError, match="cannot move there"):
        for _ in range(5):
            session.request("translate 0.3 0 0")
    flange = env.state.flange_pose[0]
    assert np.allclose(flange, session.pose[:3], atol=0.01)  # still where the last move went
    with pytest.raises(SetupError, match="no pose saved"):
        session.save_behavior(BehaviorLibrary(tmp_path / "lib"), "x")
    env.close()


def test_a_saved_pose_stays_inside_the_primitives_space(monkeypatch, tmp_path, user_library,
                                                        capsys):
    """The default pose's roll is pi: written rounded (3.1416) it left the space, and every
    episode of the saved behavior failed."""
    monkeypatch.setattr("sys.stdin", io.StringIO("save\nquit\n"))
    assert main(["scoop-setup", "--name", "as_is", "--images", str(tmp_path)]) == 0
    capsys.readouterr()
    pose = saved_pose(user_library, "as_is")
    env = gym.make("VLB-Scoop-v0").unwrapped
    try:
        space = env.primitives["scoop"].param_space
        assert space.contains(pose.astype(space.dtype)), (pose, space)
    finally:
        env.close()
