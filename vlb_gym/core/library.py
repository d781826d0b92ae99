"""The behavior library B: shipped behaviors, the user's saved ones, and files by path.

Names resolve to a shipped behavior first, then to the user's library directory
(``$VLB_BEHAVIOR_DIR``, else ``$XDG_DATA_HOME/vlb-gym/behaviors``, else
``~/.local/share/vlb-gym/behaviors``); anything with a ``/`` or ending in ``.json`` is a path.
"""

from __future__ import annotations

import hashlib
import json
import os
from importlib import resources
from pathlib import Path

import gymnasium as gym

from .compiler import CompiledBehavior, compile_behavior
from .env import PrimitiveEnv
from .runtime import BehaviorPolicy
from .files import InputFileError, is_input_file, read_limited, write_atomic
from .formats import CURRENT
from .names import is_name
from .spec import BehaviorSpec, BehaviorSpecError, parse_spec

SHIPPED = "vlb_gym.behaviors"


def user_dir() -> Path:
    """The user's behavior library directory (it need not exist yet)."""
    if os.environ.get("VLB_BEHAVIOR_DIR"):
        return Path(os.environ["VLB_BEHAVIOR_DIR"]).expanduser()
    data = os.environ.get("XDG_DATA_HOME") or Path.home() / ".local" / "share"
    return Path(data) / "vlb-gym" / "behaviors"


def shipped_behaviors() -> list[str]:
    """Names of the behaviors that ship with the package."""
    return sorted(p.name[:-5] for p in resources.files(SHIPPED).iterdir()
                  if p.name.endswith(".json"))


def is_behavior_path(ref: str) -> bool:
    """Whether a behavior reference names a file rather than a library behavior."""
    return ref.endswith(".json") or "/" in ref or "\\" in ref


def _read(path: Path) -> tuple[BehaviorSpec, str, Path]:
    try:
        text = read_limited(path, what="behavior file")
    except InputFileError as exc:
        raise BehaviorSpecError(str(exc), "json") from None
    return parse_spec(text, str(path)), str(path.resolve()), path.resolve().parent


class BehaviorLibrary:
    """Named behaviors: the shipped ones (unless ``shipped`` is False, e.g. to synthesize the
    paper's Behavior 1 from an empty library) plus those saved in ``directory``."""

    def __init__(self, directory: Path | None = None, shipped: bool = True):
        self.directory = Path(directory) if directory is not None else user_dir()
        self.shipped = shipped

    def _shipped(self) -> list[str]:
        return shipped_behaviors() if self.shipped else []

    def user_behaviors(self) -> list[str]:
        if not self.directory.is_dir():
            return []
        # behavior names are identifiers; NAME.transcript.json and the like are not behaviors
        return sorted(p.stem for p in self.directory.glob("*.json") if "." not in p.stem)

    def names(self) -> list[str]:
        return sorted(set(self._shipped()) | set(self.user_behaviors()))

    def __contains__(self, name: str) -> bool:
        return name in self._shipped() or is_input_file(self.directory / f"{name}.json")

    def resolve(self, ref: str, base_dir: Path | None = None
                ) -> tuple[BehaviorSpec, str, Path | None]:
        """Load ``ref`` (a name or a path, relative to ``base_dir`` if given) as a spec."""
        if is_behavior_path(ref):
            return self._read_path(ref, base_dir)
        return self.resolve_name(ref)

    def resolve_name(self, ref: str, base_dir: Path | None = None
                     ) -> tuple[BehaviorSpec, str, Path | None]:
        """Load the library behavior named ``ref``; paths are refused (what a behavior from a
        language model may reference). ``base_dir`` is ignored: names need none."""
        if not is_name(ref):
            raise BehaviorSpecError(f"{ref!r} is not a behavior name: only behaviors of the "
                                    f"library can be referenced, by name "
                                    f"({', '.join(self.names())})")
        if ref in self._shipped():
            text = resources.files(SHIPPED).joinpath(f"{ref}.json").read_bytes()
            return parse_spec(text, f"{ref}.json"), f"{ref}.json", None
        if is_input_file(self.directory / f"{ref}.json"):
            return _read(self.directory / f"{ref}.json")
        raise BehaviorSpecError(f"unknown behavior {ref!r}: known behaviors are "
                                f"{', '.join(self.names())}; or give a path to a .json file")

    @staticmethod
    def _read_path(ref: str, base_dir: Path | None) -> tuple[BehaviorSpec, str, Path]:
        path = Path(ref).expanduser()
        if not path.is_absolute() and base_dir is not None:
            path = base_dir / path
        return _read(path)

    def save(self, spec: BehaviorSpec, overwrite: bool = False) -> Path:
        """Write ``spec`` as ``<directory>/<name>.json`` atomically; never over a shipped one."""
        if spec.name in shipped_behaviors():
            raise BehaviorSpecError(f"{spec.name!r} is a shipped behavior; choose another name")
        path = self.directory / f"{spec.name}.json"
        if path.exists() and not overwrite:
            raise BehaviorSpecError(f"{path}: a behavior named {spec.name!r} exists already")
        write_atomic(path, spec_json(spec))
        return path

    def load_all(self) -> tuple[dict[str, BehaviorSpec], dict[str, str]]:
        """Every behavior that loads, by name, and why each of the others does not: one broken
        file in the user's library does not hide the rest."""
        specs, broken = {}, {}
        for name in self.names():
            try:
                specs[name] = self.resolve_name(name)[0]
            except BehaviorSpecError as exc:
                broken[name] = str(exc)
        return specs, broken


def spec_json(spec: BehaviorSpec, content_only: bool = False) -> str:
    """A behavior file as pretty JSON (aliases, no defaults), in the current format; with
    ``content_only``, the behavior alone (no certificate, no format: what its digest covers)."""
    data = spec.model_dump(by_alias=True, exclude_defaults=True,
                           exclude={"certificate", "format"} if content_only else {"format"})
    if not content_only:
        data = {"format": CURRENT["behavior"], **data}
    return json.dumps(data, indent=2) + "\n"


def compile_spec(spec: BehaviorSpec, env: gym.Env, source: str, base_dir: Path | None = None,
                 library: BehaviorLibrary | None = None, names_only: bool = False
                 ) -> CompiledBehavior:
    """Compile a spec against ``env`` (wrappers are looked through), checking its env id. With
    ``names_only`` its sub-behaviors must be library behaviors named, never paths."""
    interface = env.unwrapped
    if not isinstance(interface, PrimitiveEnv):
        raise TypeError(f"behaviors run on PrimitiveEnv environments, not "
                        f"{type(interface).__name__}")
    if spec.env is not None and spec.env != interface.env_id:
        raise BehaviorSpecError(f"{source}: env: behavior is written for {spec.env!r}, "
                                f"not {interface.env_id!r}")
    library = library or BehaviorLibrary()
    lookup = library.resolve_name if names_only else library.resolve
    return compile_behavior(spec, interface, source, lookup, base_dir)


def compile_for(ref: str, env: gym.Env, library: BehaviorLibrary | None = None
                ) -> CompiledBehavior:
    """Resolve ``ref`` and compile it against ``env``."""
    library = library or BehaviorLibrary()
    spec, source, base_dir = library.resolve(ref)
    return compile_spec(spec, env, source, base_dir, library)


def load_behavior(ref: str, env: gym.Env, library: BehaviorLibrary | None = None
                  ) -> BehaviorPolicy:
    """A ready-to-run policy for behavior ``ref`` (a name or a path) on ``env``."""
    return BehaviorPolicy(compile_for(ref, env, library), env.unwrapped)


def behavior_tree(behavior: CompiledBehavior) -> list[CompiledBehavior]:
    """A compiled behavior and its sub-behaviors, each once, ordered by source."""
    seen: dict[str, CompiledBehavior] = {}
    stack = [behavior]
    while stack:
        current = stack.pop()
        if current.source not in seen:
            seen[current.source] = current
            stack.extend(n.child for n in current.nodes.values() if n.child is not None)
    return [seen[source] for source in sorted(seen)]


class BehaviorLoader:
    """Behavior graphs as the policies of campaigns (policy kind ``behavior``): a name, resolved
    in ``ref.library`` (default: the user's library), or a JSON file."""

    runs_code = False  # a behavior file is data, checked before anything runs
    replay_options = ("--behavior",)

    def load(self, ref, env: gym.Env) -> BehaviorPolicy:
        library = BehaviorLibrary(Path(ref.library)) if ref.library else None
        return load_behavior(ref.ref, env, library)

    def files(self, ref, policy: BehaviorPolicy) -> list[Path]:
        """The behavior's files and its sub-behaviors' (shipped ones are no file of the user's),
        each as read and, where that differs, as a worker reaches it: from its parent's folder
        or the library's, as the driver resolved those, through no link the worker may lack (a
        symlinked folder or library file)."""
        library = Path(ref.library).expanduser() if ref.library else user_dir()
        paths = []
        for behavior in behavior_tree(policy.behavior):
            if not Path(behavior.source).is_absolute():
                continue
            paths.append(Path(behavior.source))
            for node in behavior.spec.nodes:
                if node.behavior is None:
                    continue
                if is_behavior_path(node.behavior):
                    child = Path(behavior.source).parent / Path(node.behavior).expanduser()
                else:
                    child = library.resolve() / f"{node.behavior}.json"
                if child.is_file():
                    paths.append(Path(os.path.abspath(child)))
        return list(dict.fromkeys(paths))

    def content(self, ref, policy: BehaviorPolicy) -> dict:
        """A digest of the whole tree of behaviors and their documents, by source (a
        behavior's certificate, which records this digest, left out)."""
        tree = behavior_tree(policy.behavior)
        digest = hashlib.sha256()
        for behavior in tree:
            digest.update(spec_json(behavior.spec, content_only=True).encode())
        return {"sha256": digest.hexdigest(),
                "behaviors": {b.source: b.spec.model_dump(by_alias=True, exclude_defaults=True,
                                                          exclude={"certificate", "format"})
                              for b in tree}}

    def trained_env(self, ref) -> None:
        return None
