"""Interactive set-up of the scooping sensing pose (the paper's Sec. V-B).

The user says in words how to move the end-effector; the abstractor turns each request into calls
of three helpers -- ``translate`` and ``rotate`` the end-effector by an amount, ``save`` the current
pose -- sent back as data (a JSON list of calls, checked against a schema), never as code. The arm
moves in the simulation, the wrist camera's view is written to an image file, and the saved pose
becomes the sensing pose of a copy of ``scoop_repeatedly`` in the behavior library. Without a
language model the same helpers are typed as commands (``translate 0 0.05 0``). ``vlb
scoop-setup`` runs a session on stdin.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Annotated, Any, Literal, Union

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, TypeAdapter, ValidationError

from vlb_gym.core.chat import ChatModel
from vlb_gym.core.errors import UserError
from vlb_gym.core.library import BehaviorLibrary
from vlb_gym.core.spec import BehaviorSpecError


MAX_STEP_M = 0.3  # largest translation one call may ask for
MAX_STEP_DEG = 90.0
SYSTEM = """You help a user choose the sensing pose of a robot arm that scoops sand. The arm's \
wrist camera must see both containers from that pose. Translate each user request into calls of \
these helpers, as JSON only: {"calls": [...]} with each call one of
  {"helper": "translate", "dx": M, "dy": M, "dz": M}  move the end-effector by metres in the robot \
base frame: x forward (away from the robot), y to the robot's left, z up;
  {"helper": "rotate", "droll": D, "dpitch": D, "dyaw": D}  turn it by degrees about the base \
frame's x, y and z axes;
  {"helper": "save"}  keep the current pose as the sensing pose (only when the user is satisfied).
At most {max_m} m and {max_deg} degrees per call. Reply with the JSON object only."""


class _Call(BaseModel):
    model_config = ConfigDict(extra="forbid")


class Translate(_Call):
    helper: Literal["translate"]
    dx: float = Field(0.0, ge=-MAX_STEP_M, le=MAX_STEP_M)
    dy: float = Field(0.0, ge=-MAX_STEP_M, le=MAX_STEP_M)
    dz: float = Field(0.0, ge=-MAX_STEP_M, le=MAX_STEP_M)


class Rotate(_Call):
    helper: Literal["rotate"]
    droll: float = Field(0.0, ge=-MAX_STEP_DEG, le=MAX_STEP_DEG)
    dpitch: float = Field(0.0, ge=-MAX_STEP_DEG, le=MAX_STEP_DEG)
    dyaw: float = Field(0.0, ge=-MAX_STEP_DEG, le=MAX_STEP_DEG)


class Save(_Call):
    helper: Literal["save"]


Call = Annotated[Union[Translate, Rotate, Save], Field(discriminator="helper")]


class Calls(_Call):
    calls: list[Call] = Field(max_length=20)


CALLS = TypeAdapter(Calls)


class SetupError(UserError, ValueError):
    """A request or command that cannot be carried out; the message says why."""


def parse_reply(reply: str) -> list[Translate | Rotate | Save]:
    """The helper calls in a model's reply, checked against the schema."""
    text = reply.strip().removeprefix("```json").removeprefix("```").removesuffix("```")
    try:
        return CALLS.validate_json(text).calls
    except ValidationError as exc:
        problems = "; ".join(f"{'.'.join(map(str, e['loc']))}: {e['msg']}"
                             for e in exc.errors()[:5])
        raise SetupError(f"the reply is not a valid list of helper calls: {problems}") from None


def parse_command(line: str) -> list[Translate | Rotate | Save]:
    """Typed commands: ``translate DX DY DZ`` (m), ``rotate DROLL DPITCH DYAW`` (deg), ``save``."""
    words = line.split()
    if not words:
        return []
    name, numbers = words[0].lower(), words[1:]
    keys = {"translate": ("dx", "dy", "dz"), "rotate": ("droll", "dpitch", "dyaw"), "save": ()}
    if name not in keys:
        raise SetupError(f"{line!r}: unknown command; use translate DX DY DZ, rotate DROLL "
                         "DPITCH DYAW, save, or quit")
    try:
        values = [float(v) for v in numbers]
    except ValueError:
        raise SetupError(f"{line!r}: arguments must be numbers") from None
    if len(values) != len(keys[name]):
        raise SetupError(f"{line!r}: {name} takes {len(keys[name])} number(s)")
    data = {"helper": name, **dict(zip(keys[name], values))}
    try:
        return CALLS.validate_python({"calls": [data]}).calls
    except ValidationError as exc:
        raise SetupError(f"{line!r}: {exc.errors()[0]['msg']}") from None


class ScoopSetup:
    """A set-up session on a ``VLB-Scoop-v0`` environment (unwrapped ``ScoopEnv``)."""

    def __init__(self, env: Any, image_dir: Path, backend: ChatModel | None = None,
                 max_rounds: int = 2):
        from vlb_gym.envs.scoop.env import DEFAULT_SENSING_POSE

        self.env, self.backend, self.max_rounds = env, backend, max_rounds
        self.image_dir = Path(image_dir)
        self.pose = np.array(DEFAULT_SENSING_POSE, dtype=float)
        self.saved: np.ndarray | None = None
        self.views = 0
        self.transcript: list[dict[str, Any]] = []

    def request(self, text: str) -> list[str]:
        """Carry out one request (words with a backend, a typed command without one)."""
        if self.backend is None:
            calls = parse_command(text)
        else:
            calls = self._ask(text)
        return [self.apply(call) for call in calls]

    def _ask(self, text: str) -> list[Translate | Rotate | Save]:
        system = SYSTEM.replace("{max_m}", str(MAX_STEP_M)).replace("{max_deg}",
                                                                     str(MAX_STEP_DEG))
        pose = ", ".join(f"{v:.3f}" for v in self.pose)
        messages = [{"role": "system", "content": system},
                    {"role": "user", "content": f"Current pose (x, y, z m; roll, pitch, yaw rad):"
                                                f" ({pose}). Request: {text}"}]
        for _ in range(self.max_rounds):
            reply = self.backend.complete(messages, CALLS.json_schema())
            record = {"request": text, "reply": reply, "error": None}
            self.transcript.append(record)
            try:
                return parse_reply(reply)
            except SetupError as exc:
                record["error"] = str(exc)
                messages += [{"role": "assistant", "content": reply},
                             {"role": "user", "content": f"{exc}. Reply with the JSON only."}]
        raise SetupError(f"no valid helper calls after {self.max_rounds} replies: "
                         f"{self.transcript[-1]['error']}")

    def apply(self, call: Translate | Rotate | Save) -> str:
        """Run one helper call; returns what happened, in words."""
        from vlb_gym.envs.scoop.kinematics import matrix_rpy, rpy_matrix

        if isinstance(call, Save):
            self.saved = self.pose.copy()
            return f"saved sensing pose {self._fmt(self.saved)}"
        target = self.pose.copy()
        if isinstance(call, Translate):
            target[:3] += [call.dx, call.dy, call.dz]
        else:
            turn = rpy_matrix(*np.radians([call.droll, call.dpitch, call.dyaw]))
            target[3:] = matrix_rpy(turn @ rpy_matrix(*self.pose[3:]))
        reason = self.env.move_to(target)
        if reason is not None:
            raise SetupError(f"cannot move there: {reason}")
        self.pose = target
        return f"moved to {self._fmt(target)}; {self.view()}"

    def view(self) -> str:
        """Write the wrist camera's view and say whether both containers are in it."""
        from PIL import Image

        self.views += 1
        path = self.image_dir / f"wrist_view_{self.views:02d}.png"
        path.parent.mkdir(parents=True, exist_ok=True)
        Image.fromarray(self.env.wrist_image()).save(path)
        problem = self.env.inadmissible_reason("scoop", self.pose)
        seen = "both containers in view" if problem is None else problem
        return f"{seen}; camera view: {path}"

    def save_behavior(self, library: BehaviorLibrary, name: str, overwrite: bool = False
                      ) -> Path:
        """A copy of ``scoop_repeatedly`` with the saved pose, added to the library."""
        if self.saved is None:
            raise SetupError("no pose saved yet: say so (or type 'save') when the view is right")
        spec = library.resolve("scoop_repeatedly")[0]
        # exact (repr), never rounded: a roll of pi rounded to 3.1416 leaves the parameter space
        pose = "(" + ", ".join(repr(float(v)) for v in self.saved) + ")"
        spec = spec.model_copy(update={
            "name": name, "variables": {**spec.variables, "sensing_pose": pose},
            "description": f"scoop_repeatedly from the sensing pose {pose} chosen with "
                           "vlb scoop-setup."})
        try:
            return library.save(spec, overwrite)
        except BehaviorSpecError as exc:
            raise SetupError(str(exc)) from None

    @staticmethod
    def _fmt(pose: Sequence[float]) -> str:
        return "(" + ", ".join(f"{v:.3f}" for v in pose) + ")"


def transcript_json(session: ScoopSetup) -> str:
    return json.dumps({"saved": None if session.saved is None else session.saved.tolist(),
                       "exchanges": session.transcript}, indent=2)
