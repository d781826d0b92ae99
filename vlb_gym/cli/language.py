"""``vlb synthesize`` and ``vlb scoop-setup``: behaviors and poses from language."""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

import gymnasium as gym

from vlb_gym.core.files import read_limited, write_atomic

from .common import (UsageError, add_env_module, add_model_options, behavior_name, check_env,
                     check_output, count, env_modules, probability, seconds)
from .library import graph_text

if TYPE_CHECKING:
    from vlb_gym.abstractor.backends import ChatBackend
    from vlb_gym.abstractor.local import Decoding


def backend_from_args(args: argparse.Namespace) -> ChatBackend:
    from vlb_gym.abstractor.backends import ModelError, ScriptedBackend, TranscriptBackend
    from vlb_gym.abstractor.served import OpenAICompatibleBackend

    chosen = [flag for flag, value in (("--scripted", args.scripted),
                                       ("--replay-transcript", args.replay_transcript),
                                       ("--base-url", args.base_url),
                                       ("--model-path", args.model_path)) if value]
    if len(chosen) != 1:
        raise UsageError("give exactly one language model: --base-url URL (with --model), "
                         "--model-path FILE.gguf, --scripted FILE or --replay-transcript FILE"
                         + (f" (got {', '.join(chosen)})" if chosen else ""))
    try:
        if args.scripted:
            return ScriptedBackend.from_file(args.scripted)
        if args.replay_transcript:
            return TranscriptBackend.from_file(args.replay_transcript)
    except ModelError as exc:  # an unreadable or malformed file of replies
        raise UsageError(str(exc)) from None
    try:
        if args.temperature < 0:
            raise ValueError(f"--temperature must be at least 0 (got {args.temperature})")
        if args.model_path:
            from vlb_gym.abstractor.local import DEFAULT_TIMEOUT, LocalBackend
            return LocalBackend(args.model_path, args.context, args.threads, args.max_tokens,
                                args.temperature, args.sampling_seed,
                                args.timeout or DEFAULT_TIMEOUT, progress=TokenProgress())
        if not args.model:
            raise UsageError("--base-url needs --model NAME")
        return OpenAICompatibleBackend(args.base_url, args.model, args.api_key_env,
                                       args.timeout or default_timeout(args.base_url),
                                       args.retries, structured_output=args.structured_output,
                                       temperature=args.temperature, max_tokens=args.max_tokens,
                                       seed=args.sampling_seed)
    except ValueError as exc:
        raise UsageError(str(exc)) from None


def default_timeout(base_url: str) -> float:
    """Seconds per request: 900 for a server on this machine or a private network (a local
    model on a CPU reads a prompt at tens of tokens/s), else 120."""
    import ipaddress
    from urllib.parse import urlsplit

    host = urlsplit(base_url).hostname or ""
    try:
        local = ipaddress.ip_address(host).is_private
    except ValueError:
        local = host == "localhost" or host.endswith((".local", ".lan", ".internal"))
    return 900.0 if local else 120.0


class TokenProgress:
    """Progress lines on stderr for a local model: a line when a request begins (the prompt is
    being read), then a tqdm line of reply tokens and tokens/s."""

    def __init__(self) -> None:
        self.bar: Any = None

    def __call__(self, decoding: Decoding) -> None:
        from tqdm import tqdm

        if decoding.tokens == 0 and not decoding.done:
            print(f"request {decoding.request}: reading the prompt ...", file=sys.stderr)
            return
        if self.bar is None:
            self.bar = tqdm(desc=f"request {decoding.request}: prompt {decoding.prompt_tokens} "
                            f"tokens in {decoding.prompt_seconds or 0:.0f} s; reply",
                            unit=" tokens", file=sys.stderr, mininterval=1.0, dynamic_ncols=True)
        self.bar.update(decoding.tokens - self.bar.n)
        if decoding.done:
            self.bar.close()
            self.bar = None


def announce_structured_output(backend: ChatBackend, command: str) -> None:
    """With ``--structured-output auto``, probe the server now (a failure is a usage error, exit
    2) and say on stderr which dialect it speaks."""
    from vlb_gym.abstractor.backends import ModelError
    from vlb_gym.abstractor.dialects import dialect_label
    from vlb_gym.abstractor.served import OpenAICompatibleBackend

    if not isinstance(backend, OpenAICompatibleBackend) or backend.structured_output != "auto":
        return
    try:
        dialect = backend.probe()
    except ModelError as exc:
        raise UsageError(str(exc)) from None
    print(f"vlb {command}: structured output: {dialect_label(dialect)}", file=sys.stderr)


def confirm_promise(args: argparse.Namespace) -> Any:
    """The confirmation step: the promise in words and as an expression, the least behavior
    that keeps it (if one does), then ``--yes`` or the user's answer on stdin (anything but
    y/yes, or no answer, declines)."""
    def confirm(promise: Any, witnesses: list[str]) -> bool:
        print(f"promise: {promise.description or '(no words given)'}\n  judged as: {promise.expr}"
              + ("\n  kept as soon as it holds: the behavior stops the first time it does"
                 if promise.as_soon_as else ""))
        if witnesses:
            print(f"  a behavior that keeps this promise: {witnesses[0]}; is that what you "
                  "meant? (a promise that a behavior doing this little keeps asks for nothing "
                  "more)")
        if args.yes and witnesses and not args.trivial_ok:
            print("  not accepted: --yes takes no promise that a least behavior keeps (it asks "
                  "for nothing more than that); answer when asked, or add --trivial-ok if the "
                  "request asks for no more")
            return False
        if args.yes:
            print("  accepted (--yes)")
            return True
        print("Certify a behavior against this promise? [y/N] ", end="", flush=True)
        answer = sys.stdin.readline().strip().lower()
        return answer in ("y", "yes")
    return confirm


def expert_promise(args: argparse.Namespace) -> Any:
    """``--promise EXPR`` (with ``--promise-words``) checked against the env's outcome
    helpers; a usage error (one line) where it is not a promise."""
    from vlb_gym.core.promise import check_promise, check_rewinds
    from vlb_gym.core.spec import BehaviorSpecError, Promise, validated
    from vlb_gym.envs.modules import EnvSetupError, make_primitive_env

    try:
        env = make_primitive_env(args.env_id, {}, env_modules(args.env_module))
    except EnvSetupError as exc:
        raise UsageError(str(exc)) from None
    try:
        promise = validated(Promise, {"expr": args.promise,
                                      "description": args.promise_words or "",
                                      "as_soon_as": args.as_soon_as},
                            "--promise", "")
        own = {name: "an observation helper (what the agent sees, not what happened)"
               for name in env.unwrapped.make_helpers().functions()}
        check_promise(promise.expr, env.unwrapped, "--promise", own)
        if promise.as_soon_as:
            check_rewinds(env.unwrapped, "--as-soon-as")
    except BehaviorSpecError as exc:
        raise UsageError(" ".join(str(exc).split())) from None
    finally:
        env.close()
    return promise


def synthesize_certified_cmd(args: argparse.Namespace, backend: ChatBackend | None) -> int:
    """``vlb synthesize --certify``: intent first (promise, its witness, confirmation, search,
    certification on fresh seeds)."""
    from vlb_gym.abstractor.certified import certify_promise, synthesize_certified
    from vlb_gym.abstractor.certify import ATTEMPTS, certification_episodes
    from vlb_gym.core.library import BehaviorLibrary, spec_json
    from vlb_gym.core.spec import spec_from_data
    from vlb_gym.verify.bounds import floor_str, one_minus_str

    if args.verify or args.uses or args.info:
        raise UsageError("--certify: --verify, --uses and --info are for the graph-first "
                         "synthesis (--certify certifies on fresh seeds, from its own search)")
    check_searchable(args.env_id, env_modules(args.env_module))
    library = BehaviorLibrary()
    name = args.name or "certified_behavior"
    path = Path(args.out) if args.out else library.directory / f"{name}.json"
    if not args.out and name in library and not args.force:
        raise UsageError(f"--name {name}: the library has a behavior of that name (use --force "
                         "to replace it, or another --name)")
    confirm = confirm_promise(args)
    if backend is None:
        got = certify_promise(args.env_id, args.description, expert_promise(args), confirm,
                              name, args.time_limit, workers=args.workers)
    else:
        got = synthesize_certified(args.env_id, args.description, backend, confirm, name,
                                   time_limit=args.time_limit, workers=args.workers)
    transcript = path.with_suffix(".transcript.json")
    if got.declined:
        print("not confirmed: nothing searched, nothing saved")
        return 1
    if not got.certified:
        where = path.with_suffix(".failed.transcript.json")
        write_atomic(where, json.dumps(got.transcript, indent=2) + "\n")
        t = got.transcript
        promises = sum(bool(d["promise"]) for d in t["drafts"]) if backend else 1
        found = sum(bool(f["program"]) for f in t["finds"])
        print(f"vlb synthesize: no behavior certified: {promises} promise(s), "
              f"{found} behavior(s) found, {len(t['certifications'])} certification(s) "
              f"failed\n  transcript: {where}", file=sys.stderr)
        return 1
    spec = spec_from_data(got.document, str(path))
    write_atomic(path, spec_json(spec))
    write_atomic(transcript, json.dumps(got.transcript, indent=2) + "\n")
    cert = spec.certificate
    print(f"{name}: {got.words} (after {got.transcript['seconds']:.0f} s)\n"
          f"  certified on {cert.successes}/{cert.episodes} fresh episodes (root seed "
          f"{cert.seed}): the promise holds with P >= {one_minus_str(cert.epsilon)} at "
          f"confidence {floor_str(cert.confidence)} (union bound over up to {ATTEMPTS} "
          f"certification campaigns of {certification_episodes()} episodes)\n"
          f"  saved: {path}\n  transcript: {transcript}\n"
          f"  check it again: vlb verify {args.env_id} --behavior {path} --certificate")
    return 0


def check_searchable(env_id: str, modules: Any) -> None:
    """A usage error unless ``env_id`` declares a search space."""
    from vlb_gym.envs.modules import EnvSetupError, make_primitive_env

    try:
        env = make_primitive_env(env_id, {}, modules or ())
    except EnvSetupError as exc:
        raise UsageError(str(exc)) from None
    try:
        if env.unwrapped.search_space() is None:
            raise UsageError(f"--certify: {env_id} declares no search space (its "
                             "PrimitiveEnv.search_space() returns None)")
    finally:
        env.close()


def cmd_synthesize(args: argparse.Namespace) -> int:
    from vlb_gym.abstractor.synthesize import SynthesisError, save, save_transcript, synthesize
    from vlb_gym.core.library import BehaviorLibrary
    from vlb_gym.verify.campaign import CampaignConfig, run_campaign

    modules = env_modules(args.env_module)
    check_env(args.env_id, {}, modules)
    if args.promise is not None and not args.certify:
        raise UsageError("--promise states the promise of a certified synthesis: add --certify")
    if args.as_soon_as and args.promise is None:
        raise UsageError("--as-soon-as says how --promise is kept: add --promise EXPR")
    backend = None if args.promise is not None else backend_from_args(args)
    library = BehaviorLibrary()
    if args.out:  # checked before the model is asked; the transcript goes beside the behavior
        inputs = (args.info, args.scripted, args.replay_transcript)
        check_output(args.out, inputs, args.force, "--out")
        check_output(str(Path(args.out).with_suffix(".transcript.json")), inputs, True, "--out")
    info = ""
    if args.info:
        try:
            info = read_limited(args.info, what="--info file").decode()
        except UnicodeDecodeError:
            raise UsageError(f"--info {args.info}: not UTF-8 text") from None
    if args.certify:
        if backend is not None:
            announce_structured_output(backend, "synthesize")
        return synthesize_certified_cmd(args, backend)
    announce_structured_output(backend, "synthesize")
    try:
        result = synthesize(args.env_id, args.description, backend, library, info,
                            tuple(args.uses), args.name, args.max_rounds)
    except SynthesisError as exc:
        where = Path(args.out).with_suffix(".failed.transcript.json") if args.out else \
            library.directory / "failed" / f"{time.strftime('%Y%m%d-%H%M%S')}.transcript.json"
        save_transcript(exc.transcript, where)
        print(f"vlb synthesize: error: {exc}\n  transcript: {where}", file=sys.stderr)
        return 1
    compiled = result.compiled
    if result.from_library:
        print(f"{compiled.name} is already in the behavior library ({compiled.source}); "
              "nothing asked")
        path = Path(compiled.source)
    else:
        path = save(result, library, Path(args.out) if args.out else None, args.force)
        print(f"{compiled.name}: valid after {result.rounds} round(s) with {backend.name}")
        print(f"  saved: {path}\n  transcript: {path.with_suffix('.transcript.json')}")
    print(graph_text(compiled))
    if args.verify:
        config = CampaignConfig(args.env_id, str(path) if args.out else compiled.name,
                                args.verify, args.epsilon, seed=args.seed, env_modules=modules)
        print(run_campaign(config).summary())
    return 0


def cmd_scoop_setup(args: argparse.Namespace) -> int:
    from vlb_gym.abstractor.backends import ModelError
    from vlb_gym.envs.scoop.setup import ScoopSetup, SetupError, transcript_json
    from vlb_gym.core.library import BehaviorLibrary

    backend = (backend_from_args(args) if (args.base_url or args.scripted or args.model_path)
               else None)
    if backend is not None:
        announce_structured_output(backend, "scoop-setup")
    env = gym.make("VLB-Scoop-v0").unwrapped
    env.reset(seed=args.seed)
    session = ScoopSetup(env, Path(args.images), backend)
    library = BehaviorLibrary()
    if backend is None:
        print("No language model configured: type commands -- translate DX DY DZ (m, base "
              "frame: x forward, y left, z up), rotate DROLL DPITCH DYAW (degrees), save, quit.")
    else:
        print(f"Say how to move the end-effector ({backend.name}); 'quit' to stop.")
    print(session.view())
    while True:
        if sys.stdin.isatty():
            print("> ", end="", flush=True)
        line = sys.stdin.readline()
        if not line or line.strip().lower() in ("quit", "exit", "q"):
            break
        if not line.strip():
            continue
        try:
            for message in session.request(line.strip()):
                print(message)
        except (SetupError, ModelError) as exc:
            print(f"error: {exc}")
    env.close()
    if backend is not None:
        write_atomic(Path(args.images) / "transcript.json", transcript_json(session) + "\n")
    if session.saved is None:
        print("no pose saved; nothing written")
        return 1
    try:
        path = session.save_behavior(library, args.name, args.force)
    except SetupError as exc:
        print(f"vlb scoop-setup: error: {exc}", file=sys.stderr)
        return 2
    print(f"wrote {path}\nverify it: vlb verify VLB-Scoop-v0 --behavior {args.name} "
          "--episodes 59 --epsilon 0.05 --workers 2")
    return 0


def add_parsers(sub: argparse._SubParsersAction) -> None:
    y = sub.add_parser("synthesize", help="compose a behavior from a description with an LLM",
                       description="Algorithm 1 of the paper: ask a language model for a behavior "
                       "graph over the environment's primitives, validate it (JSON, schema, "
                       "references, graph, expressions, dry run), feed errors back for repair, and "
                       "add the valid behavior to the library (or --out). A transcript of prompts, "
                       "replies and errors is saved beside the result.")
    y.add_argument("env_id", metavar="ENV_ID", help="e.g. VLB-GridExplore-v0")
    y.add_argument("description", metavar="DESCRIPTION", help="the desired behavior, in words")
    y.add_argument("--info", metavar="FILE", help="extra information for the model (the "
                   "paper's string I)")
    y.add_argument("--uses", nargs="+", default=[], metavar="BEHAVIOR",
                   help="existing behaviors the new one should build on")
    y.add_argument("--name", type=behavior_name, help="name of the new behavior; if the library has it already, it "
                   "is used and the model is not asked")
    y.add_argument("--out", metavar="FILE", help="write here instead of the user library")
    y.add_argument("--force", action="store_true", help="replace an existing file")
    y.add_argument("--max-rounds", type=count(1), default=3, metavar="N",
                   help="replies to try, repairs included")
    add_model_options(y)
    y.add_argument("--replay-transcript", metavar="FILE",
                   help="replay the replies of an earlier synthesize transcript")
    y.add_argument("--certify", action="store_true",
                   help="intent first: the model writes the behavior's promise, you confirm it, "
                   "and a search finds a behavior that certifies it on fresh seeds")
    y.add_argument("--yes", action="store_true",
                   help="with --certify: accept the promise without asking")
    y.add_argument("--trivial-ok", action="store_true",
                   help="with --yes: accept also a promise that one of the env's least "
                   "behaviors keeps (a request that asks for no more, e.g. 'sense once')")
    y.add_argument("--promise", metavar="EXPR",
                   help="with --certify: the promise itself, an expression over the env's "
                   "outcome helpers (no model is asked); it is type-checked, tried on the "
                   "env's least behaviors, and confirmed unless --yes")
    y.add_argument("--promise-words", metavar="TEXT",
                   help="with --promise: the promise in plain words, shown when confirming")
    y.add_argument("--as-soon-as", action="store_true",
                   help="with --promise: the behavior stops as soon as the promise holds (it "
                   "held after no earlier step)")
    y.add_argument("--time-limit", type=seconds, default=240.0, metavar="SECONDS",
                   help="with --certify: seconds the search may take")
    y.add_argument("--workers", type=count(1), default=1, metavar="N",
                   help="with --certify: processes running the certification campaign")
    y.add_argument("--verify", type=count(1), metavar="N",
                   help="then verify the result with N episodes")
    y.add_argument("--epsilon", type=probability, default=0.05, metavar="EPS",
                   help="with --verify: the claim is P[success] >= 1 - EPS")
    y.add_argument("--seed", type=count(0), default=0, help="with --verify: the campaign seed")
    add_env_module(y)
    y.set_defaults(func=cmd_synthesize)

    z = sub.add_parser("scoop-setup", help="choose the scooping sensing pose in words",
                       description="Move the scoop arm's end-effector by saying how (an LLM turns "
                       "each request into translate / rotate / save helper calls) or, without a "
                       "model, by typing those commands; each move writes the wrist camera's "
                       "view to an image. The saved pose becomes the sensing pose of a copy of "
                       "scoop_repeatedly in the behavior library. Reads requests from stdin.")
    z.add_argument("--name", type=behavior_name, default="my_scoop", help="name of the behavior to write")
    z.add_argument("--images", default="scoop_setup", metavar="DIR",
                   help="where the camera views go")
    z.add_argument("--seed", type=count(0), default=0, help="which container placement to show")
    z.add_argument("--force", action="store_true", help="replace a behavior of that name")
    add_model_options(z)
    z.set_defaults(func=cmd_scoop_setup, replay_transcript=None)
