"""Certified synthesis: how often does a language model's behavior verify, and do the task?

    python benchmarks/synthesis_eval.py --model-path qwen2.5-coder-1.5b-instruct-q4_k_m.gguf \
        [--model-path another.gguf] [--samples 1] [--tasks NAME ...] [--episodes 100] \
        [--out benchmarks/results/synthesis]
    python benchmarks/synthesis_eval.py --replay benchmarks/results/synthesis

For every model, task (:mod:`benchmarks.synthesis_tasks`) and sample, Algorithm 1 runs with the
local backend (grammar-constrained decoding, up to ``--max-rounds`` replies); a valid behavior is
then run for ``--episodes`` episodes (campaign seed 0) and counted twice: *verified* (rho_B = +1,
the certificates) and *done* (verified and the task's own check, from the ground truth). A task
is **certified** for a sample when all N episodes are done: P[success] >= 1 - eps with confidence
1 - (1 - eps)^N (99.4% for N = 100, eps = 0.05). Sample 0 decodes greedily, sample s > 0 at
temperature 0.7 with seed s.

Every transcript and valid behavior is written under ``--out/<model>/``, with ``results.csv``
(one row per sample) and ``results.md`` (per model: validity rate, mean rounds, certified rate,
tokens, seconds; then per task). ``--replay DIR`` re-runs the saved transcripts without a model
(:class:`~vlb_gym.abstractor.backends.TranscriptBackend`): each must reach the same outcome
round by round, and the tables are rebuilt from the replay (tokens and seconds are the live
run's, from the transcripts).
"""

from __future__ import annotations

import argparse
import csv
import json
import platform
import statistics
import sys
import tempfile
import time
from dataclasses import asdict, dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from benchmarks.synthesis_tasks import ENV_ID, TASKS, Task, evaluate  # noqa: E402
from vlb_gym.abstractor.backends import ChatBackend, TranscriptBackend  # noqa: E402
from vlb_gym.abstractor.synthesize import (SynthesisError, save_transcript,  # noqa: E402
                                           synthesize)
from vlb_gym.core.files import write_atomic  # noqa: E402
from vlb_gym.core.library import BehaviorLibrary, spec_json  # noqa: E402

SAMPLE_TEMPERATURE = 0.7


@dataclass
class Sample:
    """One model's attempt at one task, and what its behavior did."""

    model: str
    task: str
    difficulty: int
    sample: int
    valid: bool
    rounds: int
    layers: str  # the failing layer of each round, "ok" for the valid one
    prompt_tokens: int
    reply_tokens: int
    seconds: float
    episodes: int = 0
    verified: int = 0
    done: int = 0
    confidence: float = 0.0
    failure: str = ""

    @property
    def certified(self) -> bool:
        return self.valid and self.episodes > 0 and self.done == self.episodes


def cost(rounds: list[dict]) -> tuple[int, int, float]:
    """Prompt tokens, reply tokens and decoding seconds of a transcript's rounds, every draw of
    every round (a round's ``usage`` is a list of draws: a reply that repeated a rejected one
    was drawn again)."""
    draws = [draw for r in rounds for draw in r.get("usage") or []]
    return (sum(d.get("prompt_tokens") or 0 for d in draws),
            sum(d.get("reply_tokens") or 0 for d in draws),
            round(sum(d.get("seconds") or 0 for d in draws), 1))


def attempt(task: Task, backend: ChatBackend, model: str, sample: int, folder: Path,
            episodes: int, max_rounds: int) -> Sample:
    """Synthesize ``task`` once with ``backend``, save the transcript (and the behavior), and
    verify a valid result."""
    stem = folder / f"{task.name}-{sample}"
    with tempfile.TemporaryDirectory() as user_dir:
        library = BehaviorLibrary(Path(user_dir), shipped=task.library)
        started = time.perf_counter()
        try:
            result = synthesize(ENV_ID, task.description, backend, library, max_rounds=max_rounds)
            transcript, compiled = result.transcript, result.compiled
        except SynthesisError as exc:
            transcript, compiled = exc.transcript, None
        seconds = time.perf_counter() - started
    transcript["task"] = task.name
    save_transcript(transcript, stem.with_suffix(".transcript.json"))
    rounds = transcript["rounds"]
    record = Sample(model, task.name, task.difficulty, sample, compiled is not None, len(rounds),
                    " ".join(r["layer"] or "ok" for r in rounds), *cost(rounds))
    record.seconds = record.seconds or round(seconds, 1)
    if compiled is None:
        record.failure = (rounds[-1]["error"] or "")[:200]
        return record
    path = stem.with_suffix(".json")
    write_atomic(path, spec_json(compiled.spec))
    outcome = evaluate(task, path, episodes)
    record.episodes, record.verified, record.done = outcome.episodes, outcome.verified, \
        outcome.task_done
    record.confidence = round(outcome.confidence, 4)
    record.failure = "; ".join(f"episode {i}: {why}" for i, why in outcome.failures[:1])[:200]
    return record


def run_models(args: argparse.Namespace, tasks: list[Task]) -> list[Sample]:
    from vlb_gym.abstractor.local import LocalBackend

    samples = []
    for model_path in args.model_path:
        backend = LocalBackend(model_path, max_tokens=args.max_tokens)
        model = Path(model_path).stem
        folder = args.out / model
        folder.mkdir(parents=True, exist_ok=True)
        for task in tasks:
            for sample in range(args.samples):
                backend.temperature = 0.0 if sample == 0 else SAMPLE_TEMPERATURE
                backend.seed = sample
                record = attempt(task, backend, model, sample, folder, args.episodes,
                                 args.max_rounds)
                samples.append(record)
                print(f"{model} {task.name} #{sample}: {'valid' if record.valid else 'invalid'} "
                      f"after {record.rounds} round(s) [{record.layers}], {record.reply_tokens} "
                      f"tokens, {record.seconds:.0f} s; done {record.done}/{record.episodes}",
                      flush=True)
    return samples


def replay(folder: Path, tasks: list[Task], episodes: int) -> list[Sample]:
    """Re-run every saved transcript with its own replies; each must end as it did."""
    by_name = {task.name: task for task in tasks}
    samples, mismatches = [], []
    for path in sorted(folder.glob("*/*.transcript.json")):
        saved = json.loads(path.read_text())
        task = by_name.get(saved.get("task"))
        if task is None:
            continue
        sample = int(path.name.removesuffix(".transcript.json").rsplit("-", 1)[1])
        with tempfile.TemporaryDirectory() as scratch:
            record = attempt(task, TranscriptBackend.from_file(path), path.parent.name, sample,
                             Path(scratch), episodes, len(saved["rounds"]))
            again = json.loads((Path(scratch) / path.name).read_text())
        if [r["error"] for r in again["rounds"]] != [r["error"] for r in saved["rounds"]]:
            mismatches.append(path)
        record.prompt_tokens, record.reply_tokens, record.seconds = cost(saved["rounds"])
        samples.append(record)
    if mismatches:
        sys.exit("replay differs from the live run: " + ", ".join(map(str, mismatches)))
    return samples


def tables(samples: list[Sample], episodes: int) -> str:
    """The Markdown summary: per model, then per task."""
    lines = [f"Certified: all {episodes} episodes verified (rho_B = +1) and doing the task, "
             f"i.e. P[success] >= 0.95 at confidence {1 - 0.95 ** episodes:.1%}.", "",
             "| model | samples | valid | mean rounds | verified N/N | certified | "
             "mean reply tokens | mean s/sample |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    models = sorted({s.model for s in samples})
    for model in models:
        mine = [s for s in samples if s.model == model]
        lines.append(
            f"| {model} | {len(mine)} | {sum(s.valid for s in mine) / len(mine):.0%} | "
            f"{statistics.mean(s.rounds for s in mine):.2f} | "
            f"{sum(s.valid and s.verified == s.episodes for s in mine) / len(mine):.0%} | "
            f"**{sum(s.certified for s in mine) / len(mine):.0%}** | "
            f"{statistics.mean(s.reply_tokens for s in mine):.0f} | "
            f"{statistics.mean(s.seconds for s in mine):.0f} |")
    lines += ["", "| task | difficulty | " + " | ".join(models) + " |",
              "|---|---:|" + "---|" * len(models)]
    for task in dict.fromkeys(s.task for s in samples):
        row = []
        for model in models:
            mine = [s for s in samples if s.model == model and s.task == task]
            row.append(", ".join(
                (f"done {s.done}/{s.episodes}" + (" ✔" if s.certified else "")) if s.valid
                else f"invalid ({s.layers})" for s in mine) or "-")
        difficulty = next(s.difficulty for s in samples if s.task == task)
        lines.append(f"| {task} | {difficulty} | " + " | ".join(row) + " |")
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--model-path", action="append", metavar="FILE.gguf")
    source.add_argument("--replay", type=Path, metavar="DIR")
    parser.add_argument("--samples", type=int, default=1)
    parser.add_argument("--tasks", nargs="+", metavar="NAME")
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--max-rounds", type=int, default=3)
    parser.add_argument("--max-tokens", type=int, default=1500)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/synthesis"))
    args = parser.parse_args()
    tasks = [t for t in TASKS if not args.tasks or t.name in args.tasks]
    started = time.perf_counter()
    samples = replay(args.replay, tasks, args.episodes) if args.replay else run_models(args, tasks)
    table = tables(samples, args.episodes)
    print(f"\n{platform.machine()}, {platform.python_version()}, "
          f"{time.perf_counter() - started:.0f} s\n\n{table}")
    out = args.replay or args.out
    with (out / "results.csv").open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(asdict(samples[0])))
        writer.writeheader()
        writer.writerows(asdict(s) for s in samples)
    write_atomic(out / "results.md", table)


if __name__ == "__main__":
    main()
