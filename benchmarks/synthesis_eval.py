"""Certified synthesis, intent first: does a language model's promise certify, and is it the task?

    python benchmarks/synthesis_eval.py --model-path qwen2.5-coder-1.5b-instruct-q4_k_m.gguf \
        [--model-path another.gguf] [--samples 1] [--tasks FILE.py] [--only NAME ...] \
        [--out benchmarks/results/synthesis]
    python benchmarks/synthesis_eval.py --base-url http://127.0.0.1:11434 --model qwen2.5-coder \
        [--structured-output auto] ...
    python benchmarks/synthesis_eval.py --promises [--tasks FILE.py] [--out DIR]
    python benchmarks/synthesis_eval.py --tasks FILE.py --list
    python benchmarks/synthesis_eval.py --replay benchmarks/results/synthesis [--out DIR]

For every model, task and sample, the pipeline of :mod:`vlb_gym.abstractor.certified` runs with
the local backend (or the served model, with the same temperature, seed, token limit and
redraws) (the model writes the promise, accepted as ``--yes`` would: not one that a least
behavior keeps, unless the task asks for no more, ``Task.trivial_ok`` as ``--trivial-ok``; a
search finds a behavior that keeps it and certifies it on fresh seeds). With ``--promises`` no model runs:
each task's faithful promise (``Task.promise``, what an expert would write) goes to the search
as ``vlb synthesize --certify --promise`` would, so the search's figure is measured apart from
the model's (model name ``promises``). Each certified behavior is then run again on its
certification episodes by :func:`benchmarks.synthesis_tasks.evaluate`, which also applies the
task's own check (from the ground truth). Columns:

* *promise*: the model wrote a promise that checks;
* *certified*: the promise was certified, P >= 0.95 with confidence >= 0.99 on fresh seeds (the
  search's union bound over its certification attempts, :mod:`vlb_gym.abstractor.search`);
* *done*: certified, and the task's check passed on every certification episode;
* *faithful*: on every episode where the promise was judged, its verdict equals the check's (a
  wrong promise shows here, never hidden).

Tasks are ``benchmarks.synthesis_tasks.TASKS`` (a development set: the pipeline's prompts,
worked examples and search space were written while looking at them) or ``--tasks FILE.py``, a
file defining ``TASKS``, a list of ``Task(name, description, difficulty, library, reference,
check)`` with ``check(state, result) -> str | None`` (import them from
``benchmarks.synthesis_tasks``); its results must be written outside the repository.

Transcripts, certified behaviors, ``results.csv`` and ``results.md`` go to ``--out/<model>/``
and ``--out``. ``--replay DIR`` re-runs the saved transcripts without a model: each must reach
the same promises and behaviors; its tables go to ``--out`` (default: a temporary directory,
never the committed files).
"""

from __future__ import annotations

import argparse
import csv
import importlib.util
import json
import platform
import statistics
import sys
import tempfile
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import BaseModel, Field, ValidationError

REPOSITORY = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPOSITORY))

from benchmarks.synthesis_tasks import TASKS, Task, evaluate  # noqa: E402
from vlb_gym.abstractor.backends import (ModelError, ChatBackend,  # noqa: E402
                                         TranscriptBackend)
from vlb_gym.abstractor.certified import (Seeds, certify_promise,  # noqa: E402
                                          synthesize_certified)
from vlb_gym.core.library import BehaviorLibrary  # noqa: E402
from vlb_gym.core.promise import words  # noqa: E402
from vlb_gym.core.spec import Promise  # noqa: E402
from vlb_gym.core.files import (InputFileError, load_json, read_limited,  # noqa: E402
                                write_atomic)

SAMPLE_TEMPERATURE = 0.7
MAX_REPLAYED_PROGRAMS = 10_000_000  # a transcript's search budget a replay accepts


@dataclass
class Sample:
    """One model's attempt at one task, and what its behavior did."""

    model: str
    task: str
    difficulty: int
    sample: int
    promise: str
    promises: int  # promises written (drafts that checked)
    requests: int  # model requests
    certified: bool
    candidate: str
    episodes: int
    verified: int
    done: int
    judged: int
    faithful: int
    seconds: float
    failure: str = ""

    @property
    def task_done(self) -> bool:
        return self.certified and self.done == self.episodes

    @property
    def is_faithful(self) -> bool:
        return self.certified and self.faithful == self.judged


def acceptance(task: Task):
    """The confirmation ``vlb synthesize --yes`` gives for ``task``: every promise but one that
    a least behavior keeps (it asks for nothing more), unless the task asks for no more
    (``--trivial-ok``)."""
    def accept(promise: Promise, witnesses: list[str]) -> bool:
        return task.trivial_ok or not witnesses
    return accept


def attempt(task: Task, backend: ChatBackend | None, model: str, sample: int, folder: Path,
            budgets: list[int] | None = None, seeds: Seeds | None = None,
            workers: int = 1) -> Sample:
    """Run the pipeline for ``task`` once (with ``backend``, or with the task's own promise
    where it is None), save its transcript (and behavior), and check a certified behavior
    against the task on its certification episodes (``budgets`` and ``seeds``: a replay's, see
    :mod:`~vlb_gym.abstractor.certified`)."""
    stem = folder / f"{task.name}-{sample}"
    library = BehaviorLibrary(Path(tempfile.mkdtemp(prefix="no-user-behaviors-"))) \
        if task.library else None  # the shipped behaviors, where the task allows them
    if backend is None:
        promise = Promise(expr=task.promise or "", description="")
        got = certify_promise(task.env_id, task.description, promise, acceptance(task),
                              task.name, seeds=seeds, budgets=budgets, library=library,
                              workers=workers)
    else:
        got = synthesize_certified(task.env_id, task.description, backend, acceptance(task),
                                   task.name, seeds=seeds, budgets=budgets, library=library,
                                   workers=workers)
    seconds = got.transcript["seconds"]  # the pipeline's wall time, as the transcript says
    got.transcript["task"] = task.name
    write_atomic(stem.with_suffix(".transcript.json"), json.dumps(got.transcript, indent=2) + "\n")
    drafts = got.transcript["drafts"]
    record = Sample(model, task.name, task.difficulty, sample,
                    words(got.promise.expr, got.promise.as_soon_as) if got.promise else "",
                    sum(d["promise"] is not None for d in drafts) if backend else 1,
                    sum(len(d["rounds"]) for d in drafts), got.certified, "", 0, 0, 0, 0, 0,
                    seconds)
    if not got.certified:
        record.failure = json.dumps(got.transcript["certifications"]
                                    or got.transcript["finds"][:1])[:200]
        return record
    path = stem.with_suffix(".json")
    write_atomic(path, json.dumps(got.document, indent=2) + "\n")
    certificate = got.certificate
    outcome = evaluate(task, path, certificate.episodes, certificate.seed)
    record.candidate = got.words or ""
    record.episodes, record.verified, record.done = outcome.episodes, outcome.verified, \
        outcome.task_done
    record.judged, record.faithful = outcome.judged, outcome.faithful
    record.failure = "; ".join(f"episode {i}: {why}" for i, why in outcome.failures[:1])[:200]
    return record


def backends(args: argparse.Namespace) -> list[tuple[str, ChatBackend]]:
    """(name, backend) of every model asked for: GGUF files in-process, or a served model."""
    if args.base_url:
        from vlb_gym.abstractor.served import OpenAICompatibleBackend

        if not args.model:
            sys.exit("--base-url needs --model NAME")
        try:
            served = OpenAICompatibleBackend(args.base_url, args.model,
                                             structured_output=args.structured_output,
                                             timeout=args.timeout, max_tokens=args.max_tokens)
        except ValueError as exc:
            sys.exit(f"--base-url: {exc}")
        return [("".join(c if c.isalnum() or c in "-._" else "_" for c in args.model), served)]
    from vlb_gym.abstractor.local import LocalBackend

    return [(Path(p).stem, LocalBackend(p, max_tokens=args.max_tokens)) for p in args.model_path]


def run_models(args: argparse.Namespace, tasks: list[Task]) -> list[Sample]:
    samples = []
    chosen = [("promises", None)] if args.promises else backends(args)
    for model, backend in chosen:
        folder = args.out / model
        folder.mkdir(parents=True, exist_ok=True)
        for task in tasks:
            if backend is None and not task.promise:
                continue
            for sample in range(args.samples):
                if backend is not None:
                    backend.temperature = 0.0 if sample == 0 else SAMPLE_TEMPERATURE
                    backend.seed = sample
                record = attempt(task, backend, model, sample, folder, workers=args.workers)
                samples.append(record)
                print(f"{model} {task.name} #{sample}: promise {record.promise!r}; "
                      f"{'certified: ' + record.candidate if record.certified else 'not certified'}"
                      f"; done {record.done}/{record.episodes}, faithful {record.faithful}/"
                      f"{record.judged}; {record.seconds:.0f} s", flush=True)
    return samples


def replay(folder: Path, tasks: list[Task], cap: int | None = None) -> list[Sample]:
    """Re-run every saved transcript with its own replies, seeds and search budgets; each must
    end as it did (with ``cap``, a search that found nothing builds at most ``cap`` programs:
    a quicker check)."""
    by_name = {task.name: task for task in tasks}
    samples, mismatches = [], []
    for path in sorted(folder.glob("*/*.transcript.json")):
        saved = _saved_transcript(path)
        task = by_name.get(saved.get("task"))
        if task is None or "drafts" not in saved or "seeds" not in saved:
            continue
        sample = _sample_number(path)
        budgets = [f["built"] if f["program"] or cap is None else min(f["built"], cap)
                   for f in saved["finds"]]
        seeds = Seeds(list(saved["seeds"]["screen"]), list(saved["seeds"]["certify"]))
        try:
            backend = None if saved["pipeline"] == "promise" else \
                TranscriptBackend.from_file(path)
        except ModelError as exc:
            sys.exit(str(exc))
        with tempfile.TemporaryDirectory() as scratch:
            record = attempt(task, backend, path.parent.name, sample, Path(scratch), budgets,
                             seeds)
            again = json.loads((Path(scratch) / path.name).read_text())
        if _outcomes(again) != _outcomes(saved):
            mismatches.append(path)
        record.seconds = saved.get("seconds", record.seconds)
        samples.append(record)
    if mismatches:
        sys.exit("replay differs from the live run: " + ", ".join(map(str, mismatches)))
    return samples


class _Find(BaseModel):
    built: int = Field(ge=0, le=MAX_REPLAYED_PROGRAMS)
    program: str | None


class _SavedSeeds(BaseModel):
    screen: list[Annotated[int, Field(ge=0, lt=2 ** 64)]] = Field(max_length=100)
    certify: list[Annotated[int, Field(ge=0, lt=2 ** 64)]] = Field(max_length=100)


class _Draft(BaseModel):
    promise: Any
    rounds: list[Any] = Field(max_length=100)


class _Saved(BaseModel):
    """What a replay reads of a transcript (the replies are the pipeline's own to check)."""

    task: str
    pipeline: Literal["promise", "intent-first"]
    drafts: list[_Draft] = Field(max_length=100)
    finds: list[_Find] = Field(max_length=100)
    consensus: list[Any] = Field(max_length=100)
    certifications: list[Any] = Field(max_length=100)
    seeds: _SavedSeeds


def _saved_transcript(path: Path) -> dict[str, Any]:
    """A transcript to replay, read as untrusted input (a regular file of bounded size and
    nesting, the fields a replay uses checked); a problem ends the run in one line naming
    the file. A transcript of an older format (no seeds) is returned as it is, to be
    skipped."""
    try:
        saved = load_json(read_limited(path, what="transcript"), str(path))
        if isinstance(saved, dict) and "seeds" not in saved:
            return saved
        _Saved.model_validate(saved)
        return saved
    except ValidationError as exc:
        error = exc.errors()[0]
        place = ".".join(str(p) for p in error["loc"]) or "the document"
        sys.exit(f"{path}: {place}: {error['msg']}")
    except json.JSONDecodeError as exc:
        sys.exit(f"{path}: not valid JSON: {exc}")
    except (InputFileError, ValueError, OSError) as exc:
        sys.exit(f"{path}: not a transcript to replay: {exc}"[:500])


def _sample_number(path: Path) -> int:
    tail = path.name.removesuffix(".transcript.json").rsplit("-", 1)[-1]
    if not tail.isdigit() or len(tail) > 6:
        sys.exit(f"{path}: a transcript's name ends in -SAMPLE.transcript.json, a number")
    return int(tail)


def read_samples(path: Path) -> list[Sample]:
    """The samples a run wrote to ``results.csv`` (its figures as recorded)."""
    kinds = {"difficulty": int, "sample": int, "promises": int, "requests": int,
             "certified": lambda v: v == "True", "episodes": int, "verified": int, "done": int,
             "judged": int, "faithful": int, "seconds": float}
    with path.open(newline="") as handle:
        return [Sample(**{k: kinds.get(k, str)(v) for k, v in row.items()})
                for row in csv.DictReader(handle)]


def _outcomes(transcript: dict) -> list:
    """What a replay must reproduce: the promises, the behaviors found, the consensus and the
    certifications."""
    return [[d["promise"] for d in transcript["drafts"]],
            [(f["promise"], f["program"]) for f in transcript["finds"]],
            transcript["consensus"], transcript["certifications"]]


def tables(samples: list[Sample]) -> str:
    """The Markdown summary: per model, then per task."""
    lines = ["Certified: the promise held on every one of N fresh-seed episodes, N chosen so that "
             "P[success] >= 0.95 holds with confidence >= 0.99 over the search's certification "
             "attempts. Done: certified, and the task's ground-truth check passed on all N. "
             "Faithful: the promise's verdict equals the check's on every judged episode.", "",
             "| model | samples | promise | certified | **done** | faithful | "
             "median s/task | max s/task |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    models = sorted({s.model for s in samples})
    for model in models:
        mine = [s for s in samples if s.model == model]
        n = len(mine)
        lines.append(
            f"| {model} | {n} | {sum(bool(s.promise) for s in mine)}/{n} | "
            f"{sum(s.certified for s in mine)}/{n} | **{sum(s.task_done for s in mine)}/{n}** | "
            f"{sum(s.is_faithful for s in mine)}/{sum(s.certified for s in mine)} | "
            f"{statistics.median(s.seconds for s in mine):.0f} | "
            f"{max(s.seconds for s in mine):.0f} |")
    lines += ["", "| task | difficulty | " + " | ".join(models) + " |",
              "|---|---:|" + "---|" * len(models)]
    for task in dict.fromkeys(s.task for s in samples):
        row = []
        for model in models:
            mine = [s for s in samples if s.model == model and s.task == task]
            row.append("<br>".join(_cell(s) for s in mine) or "-")
        difficulty = next(s.difficulty for s in samples if s.task == task)
        lines.append(f"| {task} | {difficulty} | " + " | ".join(row) + " |")
    return "\n".join(lines) + "\n"


def _cell(s: Sample) -> str:
    promise = f"`{s.promise}`" if s.promise else "no promise"
    if not s.certified:
        return f"{promise}: not certified ({s.seconds:.0f} s)"
    verdict = "done ✔" if s.task_done else f"done {s.done}/{s.episodes}"
    faithful = "faithful" if s.is_faithful else f"faithful {s.faithful}/{s.judged}"
    return f"{promise}: certified ({s.candidate}), {verdict}, {faithful} ({s.seconds:.0f} s)"


def load_tasks(path: Path) -> list[Task]:
    """``TASKS`` of the Python file ``path``; SystemExit (one line) if it has none."""
    if not path.is_file():
        sys.exit(f"--tasks {path}: no such file")
    spec = importlib.util.spec_from_file_location(f"_external_tasks_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
    except Exception as exc:  # the user's file: its error in one line
        sys.exit(f"--tasks {path}: {type(exc).__name__}: {exc}")
    tasks = getattr(module, "TASKS", None)  # a user's module: what it defines is unknown
    if not isinstance(tasks, (list, tuple)) or not all(isinstance(t, Task) for t in tasks):
        sys.exit(f"--tasks {path}: defines no TASKS list of benchmarks.synthesis_tasks.Task")
    return list(tasks)


def select(tasks: list[Task], only: list[str] | None) -> list[Task]:
    """The tasks named in ``only`` (all without it); SystemExit for an unknown name or an
    empty selection."""
    names = [t.name for t in tasks]
    unknown = [n for n in only or [] if n not in names]
    if unknown:
        sys.exit(f"--only: unknown task(s) {', '.join(unknown)} (tasks: {', '.join(names)})")
    chosen = [t for t in tasks if not only or t.name in only]
    if not chosen:
        sys.exit("no task selected")
    return chosen


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    source = parser.add_mutually_exclusive_group()
    source.add_argument("--model-path", action="append", metavar="FILE.gguf")
    source.add_argument("--promises", action="store_true",
                        help="no model: each task's faithful promise goes to the search")
    source.add_argument("--replay", type=Path, metavar="DIR")
    source.add_argument("--base-url", metavar="URL",
                        help="a served model (OpenAI-compatible or Ollama), with --model")
    parser.add_argument("--model", metavar="NAME", help="the served model's name")
    parser.add_argument("--structured-output", default="auto", metavar="DIALECT",
                        help="the server's dialect (see vlb synthesize --help; default auto)")
    parser.add_argument("--timeout", type=float, default=900.0, metavar="SECONDS",
                        help="seconds per request to a served model")
    parser.add_argument("--tasks", type=Path, metavar="FILE.py",
                        help="a task file defining TASKS (default: the shipped development "
                             "set); it is Python, executed as it is read: run only files you "
                             "trust")
    parser.add_argument("--only", nargs="+", metavar="NAME", help="run only these tasks")
    parser.add_argument("--list", action="store_true", help="print the selected tasks and stop")
    parser.add_argument("--samples", type=int, default=1)
    parser.add_argument("--workers", type=int, default=1,
                        help="processes running each certification campaign")
    parser.add_argument("--max-tokens", type=int, default=400)
    parser.add_argument("--out", type=Path)
    args = parser.parse_args(argv)
    tasks = select(load_tasks(args.tasks) if args.tasks else list(TASKS), args.only)
    if args.list:
        for task in tasks:
            print(f"{task.name}\t{task.difficulty}")
        return
    if not (args.model_path or args.replay or args.base_url or args.promises):
        parser.error("one of --model-path, --base-url, --promises or --replay is required "
                     "(or --list)")
    if args.replay:
        args.out = args.out or Path(tempfile.mkdtemp(prefix="synthesis-replay-"))
    args.out = (args.out or REPOSITORY / "benchmarks" / "results" / "synthesis").resolve()
    if args.tasks and args.out.is_relative_to(REPOSITORY):
        sys.exit(f"--out {args.out}: results of an external task file go outside the "
                 "repository (they are not the shipped development set's)")
    started = time.perf_counter()
    samples = replay(args.replay, tasks) if args.replay else run_models(args, tasks)
    if not samples:
        sys.exit("no sample ran (no transcript of these tasks)")
    table = tables(samples)
    print(f"\n{platform.machine()}, {platform.python_version()}, "
          f"{time.perf_counter() - started:.0f} s\n\n{table}")
    args.out.mkdir(parents=True, exist_ok=True)
    with (args.out / "results.csv").open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(asdict(samples[0])))
        writer.writeheader()
        writer.writerows(asdict(s) for s in samples)
    write_atomic(args.out / "results.md", table)


if __name__ == "__main__":
    main()
