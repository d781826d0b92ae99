"""vlb_gym.verify.backends: serial, process and Ray backends give each index's result once."""

from __future__ import annotations

import functools
import itertools
import gc
import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from tests import backend_tasks as tasks
from vlb_gym.verify.backends import BACKENDS, gc_paused, run_indices
from vlb_gym.verify.campaign import Remaining
from vlb_gym.verify.chunks import count

ROOT = Path(__file__).resolve().parent.parent
SQUARES = [(i, i * i) for i in range(200)]


def gone(pid: int, within: float = 15.0) -> bool:
    """Whether process ``pid`` ends (or is a zombie) within ``within`` seconds."""
    deadline = time.monotonic() + within
    while time.monotonic() < deadline:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return True
        stat = Path(f"/proc/{pid}/stat")
        try:
            if stat.read_text().rsplit(")", 1)[1].split()[0] == "Z":  # a zombie: it ended
                return True
        except (OSError, IndexError):
            pass
        time.sleep(0.1)
    return False


def test_bad_arguments():
    with pytest.raises(ValueError, match="backend"):
        run_indices(tasks.squares, range(3), backend="threads")
    with pytest.raises(ValueError, match="workers"):
        run_indices(tasks.squares, range(3), workers=0)


def test_serial_in_order():
    assert list(run_indices(tasks.squares, range(200), backend="serial")) == SQUARES
    assert list(run_indices(tasks.squares, [5, 3, 9], backend="serial")) == [
        (5, 25), (3, 9), (9, 81)]


@pytest.mark.parametrize("workers", [1, 2])
def test_process_each_index_once(workers):
    results = list(run_indices(tasks.squares, range(200), backend="process", workers=workers))
    assert sorted(results) == SQUARES
    if workers == 1:
        assert results == SQUARES  # one worker: in order
    assert list(run_indices(tasks.squares, [], backend="process", workers=2)) == []
    some = [3, 150, 7, 8]
    assert sorted(run_indices(tasks.squares, some, workers=workers)) == sorted(
        (i, i * i) for i in some)


@pytest.mark.skipif("OMP_NUM_THREADS" in os.environ, reason="the user's own setting is kept")
def test_process_workers_compute_on_one_thread_each():
    """Regression: torch sized its pool to the machine in every worker, and a 2-worker campaign
    of an SB3 agent ran 80x slower than 1 worker."""
    pytest.importorskip("torch")
    results = dict(run_indices(tasks.thread_pools, range(4), backend="process", workers=2))
    assert all(r == {"OMP_NUM_THREADS": "1", "torch": "1"} for r in results.values()), results
    assert "OMP_NUM_THREADS" not in os.environ  # the parent's own pools are left alone


def test_process_workers_freeze_what_setup_left_alive():
    """Collections in a worker walk only what its episodes allocate (the parent is untouched)."""
    results = dict(run_indices(tasks.collector_state, range(4), backend="process", workers=2))
    assert all(r["frozen"] > 0.9 * r["built"] > 1000 for r in results.values()), results
    assert gc.get_freeze_count() == 0


@pytest.mark.parametrize("enabled", [True, False])
def test_gc_paused_restores_the_collector(enabled):
    (gc.enable if enabled else gc.disable)()
    try:
        with pytest.raises(KeyError), gc_paused():
            assert not gc.isenabled()
            raise KeyError("unpickling failed")
        assert gc.isenabled() is enabled
    finally:
        gc.enable()


@pytest.mark.timeout(60)  # a hang guard, not a timing
def test_process_setup_failure_is_raised_as_itself():
    with pytest.raises(tasks.SetupError, match="no runner today") as info:
        list(run_indices(tasks.failing_setup, range(1000), backend="process", workers=2))
    assert "failing_setup" in str(info.value.__cause__)  # the worker's traceback


def test_process_setup_failure_before_the_first_chunk_is_sent(monkeypatch):
    """A worker whose setup fails at once may be gone before the parent sends it work: the
    send's broken pipe must not hide the worker's own error (seen in CI)."""
    from vlb_gym.verify import backends

    started = backends._Worker.__init__

    def exited_before_feeding(self, *args):
        started(self, *args)
        self.process.join(30)  # the worker has reported its error and exited

    monkeypatch.setattr(backends._Worker, "__init__", exited_before_feeding)
    with pytest.raises(tasks.SetupError, match="no runner today"):
        list(run_indices(tasks.failing_setup, range(40), backend="process", workers=2))


def test_process_worker_death_reruns_the_index(tmp_path):
    marker = tmp_path / "died"
    setup = functools.partial(tasks.dies_once, str(marker))
    results = list(run_indices(setup, range(200), backend="process", workers=2))
    assert marker.exists()  # a worker did die at index 7
    assert sorted(results) == SQUARES


def test_process_worker_death_one_worker_keeps_order(tmp_path):
    setup = functools.partial(tasks.dies_once, str(tmp_path / "died"))
    assert list(run_indices(setup, range(50), backend="process", workers=1)) == SQUARES[:50]


@pytest.mark.timeout(80)  # a hang guard, not a timing
def test_process_retry_cap_names_the_index():
    with pytest.raises(RuntimeError, match="index 7: its run killed the worker process 3 times"):
        list(run_indices(tasks.dies_always, range(20), backend="process", workers=2))


@pytest.mark.parametrize("backend", ["serial", "process"])
def test_counts_past_the_index_size_are_python_integers(backend):
    """10**20 indices (past 2**63, where ``len()`` overflows): the work starts, in order from
    0 on one worker, and stops when the caller does."""
    huge = 10 ** 20
    stream = run_indices(tasks.squares, range(huge), backend=backend, workers=1)
    assert [next(stream) for _ in range(3)] == [(0, 0), (1, 1), (2, 4)]
    stream.close()
    assert count(range(huge)) == huge and count(range(huge, 0, -3)) == -(-huge // 3)
    assert count(Remaining(huge, frozenset({0, 5}))) == huge - 2
    assert [count(range(a, b, c)) for a, b, c in [(0, 0, 1), (5, 1, 1), (0, 10, 3)]] == [
        len(range(a, b, c)) for a, b, c in [(0, 0, 1), (5, 1, 1), (0, 10, 3)]]


def test_process_close_stops_workers():
    stream = run_indices(tasks.slow, range(100), backend="process", workers=2)
    pids = {next(stream)[1] for _ in range(6)}
    stream.close()
    assert pids and all(gone(pid) for pid in pids)


def test_process_exception_in_a_run_is_raised_and_stops_workers():
    stream = run_indices(tasks.slow_then_fail, range(100), backend="process", workers=2)
    pids = {next(stream)[1] for _ in range(4)}
    with pytest.raises(tasks.RunError, match="index 30 failed"):
        for _ in stream:
            pass
    assert all(gone(pid) for pid in pids)


SCRIPT = """
from tests import backend_tasks
from vlb_gym.verify.backends import run_indices

def main():
    print("results", len(list(run_indices(backend_tasks.squares, range(100), workers=2))))

{call}
"""


@pytest.mark.parametrize("guarded", [False, True])
def test_script_without_main_guard_fails_fast(tmp_path, guarded):
    script = tmp_path / "campaign_script.py"
    call = "if __name__ == '__main__':\n    main()" if guarded else "main()"
    script.write_text(textwrap.dedent(SCRIPT).format(call=call))
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          timeout=60, env=env, cwd=tmp_path, check=False)
    if guarded:
        assert done.returncode == 0, done.stderr
        assert "results 100" in done.stdout
    else:
        assert done.returncode != 0
        last = done.stderr.strip().splitlines()[-1]
        assert last.startswith("RuntimeError:") and "__name__ == '__main__'" in last, last


def campaign_records(backend: str, workers: int) -> list[dict]:
    from vlb_gym.verify.campaign import CampaignConfig

    config = CampaignConfig("VLB-GridExplore-v0", "explore_until_goal", 40)
    results = run_indices(functools.partial(tasks.campaign, config), range(40),
                          backend=backend, workers=workers)
    records = sorted((r.outcome() for r in results), key=lambda r: r["index"])
    assert [r["index"] for r in records] == list(range(40))
    return records


@pytest.fixture(scope="module")
def serial_campaign():
    return campaign_records("serial", 1)


def test_real_campaign_process_matches_serial(serial_campaign):
    assert campaign_records("process", 2) == serial_campaign
    assert any(r["rho"] > 0 for r in serial_campaign)


# ---------------------------------------------------------------------------------------- ray


def test_ray_starts_and_stops_its_own_instance(monkeypatch):
    ray = pytest.importorskip("ray")
    if ray.is_initialized():
        pytest.skip("a Ray instance is running in this process")
    # the actors run in an empty working_dir: this suite's tasks reach them through PYTHONPATH,
    # as a user's own modules would
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(filter(None, [str(ROOT),
                                                                  os.environ.get("PYTHONPATH")])))
    assert sorted(run_indices(tasks.squares, range(20), backend="ray", workers=1)) == (
        SQUARES[:20])
    assert not ray.is_initialized()


@pytest.fixture(scope="module")
def ray_instance():
    """One local Ray instance of 2 CPUs for this module's Ray tests."""
    ray = pytest.importorskip("ray")
    import logging

    if not ray.is_initialized():
        ray.init(address="local", num_cpus=2, include_dashboard=False, log_to_driver=False,
                 logging_level=logging.ERROR)
    yield ray
    ray.shutdown()


ray_test = [pytest.mark.ray, pytest.mark.xdist_group("ray"), pytest.mark.timeout(120)]


def mark_ray(function):
    for mark in ray_test:
        function = mark(function)
    return function


@mark_ray
@pytest.mark.parametrize("workers", [1, 2])
def test_ray_each_index_once(ray_instance, workers):
    assert sorted(run_indices(tasks.squares, range(200), backend="ray", workers=workers)) == (
        SQUARES)


@mark_ray
def test_ray_actors_freeze_what_setup_left_alive(ray_instance):
    results = dict(run_indices(tasks.collector_state, range(4), backend="ray", workers=2))
    assert all(r["frozen"] > 0.9 * r["built"] > 1000 for r in results.values()), results


@mark_ray
@pytest.mark.timeout(180)  # a hang guard, not a timing
def test_ray_setup_failure_is_raised_as_itself(ray_instance):
    with pytest.raises(tasks.SetupError, match="no runner today"):
        list(run_indices(tasks.failing_setup, range(1000), backend="ray", workers=2))


@mark_ray
def test_ray_worker_death_reruns_the_index(ray_instance, tmp_path):
    marker = tmp_path / "died"
    setup = functools.partial(tasks.dies_once, str(marker))
    results = list(run_indices(setup, range(200), backend="ray", workers=2))
    assert marker.exists()
    assert sorted(results) == SQUARES


@mark_ray
def test_ray_retry_cap_names_the_index(ray_instance):
    with pytest.raises(RuntimeError, match="index 7: its run killed"):
        list(run_indices(tasks.dies_always, range(20), backend="ray", workers=2))


@mark_ray
def test_ray_close_kills_actors(ray_instance):
    stream = run_indices(tasks.slow, range(100), backend="ray", workers=2)
    pids = {next(stream)[1] for _ in range(6)}
    stream.close()
    assert pids and all(gone(pid) for pid in pids)


@mark_ray
def test_real_campaign_ray_matches_serial(ray_instance, serial_campaign):
    assert campaign_records("ray", 2) == serial_campaign


def test_ray_missing_says_what_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "ray", None)
    with pytest.raises(ImportError, match=r"install vlb-gym\[ray\]"):
        next(run_indices(tasks.squares, range(3), backend="ray"))


def test_backends_listed():
    assert tuple(BACKENDS) == ("serial", "process", "ray")


@pytest.mark.parametrize("backend, workers", [("serial", 1), ("process", 2)])
def test_indices_are_taken_as_they_run_not_listed(backend, workers):
    """A campaign of 10^15 episodes starts at once: its indices are cut into chunks as workers
    take them (listing them would need petabytes)."""
    stream = run_indices(tasks.squares, range(10 ** 15), backend=backend,
                         workers=workers)
    first = [next(stream) for _ in range(5)]
    stream.close()
    assert all(i * i == square for i, square in first)


def test_chunks_are_cut_lazily_and_shrink_towards_the_end():
    from vlb_gym.verify.chunks import ChunkQueue, chunks

    queue = ChunkQueue(range(10 ** 18), 10 ** 18, 2)
    assert queue.popleft() == list(range(64)) and queue[0] == list(range(64, 128))
    queue.appendleft([7])
    assert queue.popleft() == [7] and queue.popleft()[0] == 64
    cut = chunks(list(range(1000)), 2)
    assert [i for chunk in cut for i in chunk] == list(range(1000))
    assert len(cut[0]) == 31 and len(cut[-1]) == 1  # 1000 // 32, down to one at the end


def test_a_campaign_keeps_no_list_of_its_indices():
    from vlb_gym.verify.campaign import Campaign, CampaignConfig, Remaining

    assert len(Remaining(10 ** 15, frozenset({0, 3}))) == 10 ** 15 - 2
    assert list(itertools.islice(Remaining(10 ** 15, frozenset({0, 3})), 4)) == [1, 2, 4, 5]
    seen = []

    def stop_after_three(result):
        seen.append(result)
        if len(seen) == 3:
            raise KeyboardInterrupt

    with Campaign(CampaignConfig("VLB-GridExplore-v0", "explore_until_goal", 10 ** 15,
                                 method="sequential")) as campaign:
        with pytest.raises(KeyboardInterrupt):
            campaign.run(on_result=stop_after_three)
    assert [r.index for r in seen] == [0, 1, 2]
