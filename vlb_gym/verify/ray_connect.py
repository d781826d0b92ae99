"""Connecting a campaign to Ray, within a deadline, and keeping Ray's own messages off the
user's terminal.

Without an address, a private local instance is started (``address="local"``: neither
``RAY_ADDRESS`` nor a cluster registered on the machine is attached to by accident). With one,
the host is resolved and the port probed first, then the cluster's GCS is asked who it is, so
that an unreachable address, an unresolvable host and a token-authentication refusal are each
one line (:class:`ClusterError`) within :attr:`RayOptions.timeout`. Ray's warnings while it
connects, and the node-death and other messages its driver prints while the campaign runs, go
to a log file, summarised in one note at the end.
"""

from __future__ import annotations

import contextlib
import logging
import os
import re
import signal
import socket
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

from .backends import BackendError

NOTES = logging.getLogger("vlb_gym.verify.ray")  # one-line notes for the user (stderr)
T = TypeVar("T")
DEFAULT_TIMEOUT = 30.0
DEFAULT_STALL = 60.0


@dataclass(frozen=True)
class RayOptions:
    """Where and how long: ``address`` of a cluster (``host:port`` of its GCS, ``ray://host:port``
    or ``auto``; None starts a private local instance), ``timeout`` seconds to connect, and
    ``stall`` seconds an actor may take to start before its work goes to the others (with no
    other actor alive, the campaign ends: :class:`ClusterError`)."""

    address: str | None = None
    timeout: float = DEFAULT_TIMEOUT
    stall: float = DEFAULT_STALL

    def __post_init__(self) -> None:
        for name in ("timeout", "stall"):
            value = getattr(self, name)
            if not 0 < value < float("inf"):
                raise ValueError(f"{name} must be a positive number of seconds (got {value!r})")


class ClusterError(BackendError):
    """Ray cannot be reached or started, or the cluster cannot run the campaign."""


AUTH_HINT = ("it uses token authentication: set RAY_AUTH_MODE=token and give this machine the "
             "cluster's token (RAY_AUTH_TOKEN, RAY_AUTH_TOKEN_PATH or ~/.ray/auth_token; "
             "'ray get-auth-token' on the head node prints it)")


def log_path() -> Path:
    """Where Ray's messages to this process go."""
    return Path(tempfile.gettempdir()) / f"vlb-ray-{os.getpid()}.log"


def _drop_empty_log() -> None:
    """A log of nothing is not kept."""
    with contextlib.suppress(OSError):
        if log_path().stat().st_size == 0:
            log_path().unlink()


def error_line(exc: BaseException, last: bool = False) -> str:
    """The first (or ``last``: a Ray error's cause) line of an error's text, without terminal
    colours; the error's class if it has no text."""
    lines = [re.sub(r"\x1b\[[0-9;]*m", "", line).strip() for line in str(exc).splitlines()]
    lines = [line for line in lines if line]
    return lines[-1 if last else 0] if lines else type(exc).__name__


def _within(seconds: float, what: str, call: Callable[[], T]) -> T:
    """``call()`` in a thread, waited for at most ``seconds`` (ClusterError after)."""
    box: dict[str, Any] = {}

    def target() -> None:
        try:
            box["value"] = call()
        except BaseException as exc:  # handed to the caller's thread
            box["error"] = exc

    thread = threading.Thread(target=target, name="vlb-ray-connect", daemon=True)
    thread.start()
    thread.join(max(seconds, 0.0))
    if thread.is_alive():
        raise ClusterError(f"{what}: no answer within {seconds:.0f} s (--ray-timeout)")
    if "error" in box:
        raise box["error"]
    return box["value"]


@contextlib.contextmanager
def _stderr_to(path: Path) -> Iterator[None]:
    """File descriptor 2 (where Ray's C++ code warns) appended to ``path`` for the block."""
    sys.stderr.flush()
    saved = os.dup(2)
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o600)
    os.dup2(fd, 2)
    os.close(fd)
    try:
        yield
    finally:
        sys.stderr.flush()
        os.dup2(saved, 2)
        os.close(saved)


@contextlib.contextmanager
def _sigint_held() -> Iterator[None]:
    """Hold SIGINT back (in the main thread) until the block is done; a Ctrl-C meanwhile is
    delivered, as KeyboardInterrupt, when it ends: Ctrl-C while a local Ray starts can leave
    it half started (seen: lost interrupts, crashes)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _host_port(address: str, ray: Any) -> tuple[str, int]:
    """The host and port behind ``address`` (``auto`` as Ray finds it)."""
    if address == "auto":
        from ray._private.services import canonicalize_bootstrap_address

        try:
            address = canonicalize_bootstrap_address("auto") or ""
        except (ConnectionError, ValueError) as exc:
            raise ClusterError(f"--ray-address auto: {error_line(exc)}") from None
    bare = address.split("://", 1)[-1]
    host, sep, port = bare.rpartition(":")
    if not sep or not port.isdigit():
        default = 10001 if "://" in address else 6379
        host, port = bare, str(default)
    return host.strip("[]"), int(port)


def _probe(address: str, deadline: float, ray: Any) -> None:
    """ClusterError unless something listens at ``address`` and, for a GCS address, accepts
    this process: checked before ``ray.init``, which retries such failures for minutes."""
    host, port = _host_port(address, ray)
    try:
        found = _within(deadline - time.monotonic(), f"resolving {host}",
                        lambda: socket.getaddrinfo(host, port, type=socket.SOCK_STREAM))
    except socket.gaierror as exc:
        raise ClusterError(f"cannot reach Ray at {address}: host {host!r} does not resolve "
                           f"({exc.strerror})") from None
    family, kind, proto, _, where = found[0]
    try:
        with socket.socket(family, kind, proto) as probe:
            probe.settimeout(max(deadline - time.monotonic(), 0.1))
            probe.connect(where)
    except OSError as exc:
        why = "timed out" if isinstance(exc, TimeoutError) else exc.strerror or str(exc)
        raise ClusterError(f"cannot reach Ray at {address}: {why} (port {port} of {host}; "
                           "is the head node started, and the port open?)") from None
    if "://" in address:
        return
    from ray._raylet import GcsClient
    from ray.exceptions import AuthenticationError

    gcs = f"{where[0]}:{port}"
    try:
        _within(deadline - time.monotonic(), f"Ray at {address}",
                lambda: GcsClient(address=gcs))
    except AuthenticationError:
        raise ClusterError(f"Ray at {address} refused this process: {AUTH_HINT}") from None


def _enable_found_token(address: str) -> None:
    """What ``ray.init`` does for ``auto``: a token on this machine enables token auth."""
    if address == "auto":
        from ray._private.authentication.authentication_token_setup import (
            maybe_enable_token_auth_if_token_available)

        maybe_enable_token_auth_if_token_available(warn_if_disabled=False)


def connect(ray: Any, options: RayOptions, cpus: int) -> None:
    """``ray.init``: to ``options.address``, or a private local instance of ``cpus`` CPUs;
    ClusterError in one line, within ``options.timeout``, where it cannot."""
    deadline = time.monotonic() + options.timeout
    address = options.address
    with _stderr_to(log_path()), tempfile.TemporaryDirectory(prefix="vlb-ray-") as empty:
        # an empty working_dir: Ray's workers then run there and import nothing from the
        # folder this command runs in (Ray puts that folder first on their import path else)
        settings = {"log_to_driver": False, "logging_level": logging.ERROR,
                 "runtime_env": {"working_dir": empty}}
        try:
            if address is None:  # in this thread: Ray's processes die with the thread
                with _sigint_held():  # that started them (PR_SET_PDEATHSIG)
                    ray.init(address="local", num_cpus=cpus, include_dashboard=False, **settings)
                return
            _enable_found_token(address)
            _probe(address, deadline, ray)
            _within(deadline - time.monotonic(), f"Ray at {address}",
                    lambda: ray.init(address=address, **settings))
        except ClusterError:
            raise
        except Exception as exc:
            from ray.exceptions import AuthenticationError

            if isinstance(exc, AuthenticationError):
                raise ClusterError(f"Ray at {address} refused this process: {AUTH_HINT}"
                                   ) from None
            if address is None:
                raise ClusterError(f"Ray could not start a local instance: {error_line(exc)} "
                                   f"(Ray's messages: {log_path()})") from None
            raise ClusterError(f"cannot connect to Ray at {address}: {error_line(exc)}"
                               ) from None


class _Messages:
    """Ray's driver messages (node deaths, worker crashes), appended to the log, counted."""

    def __init__(self) -> None:
        self.count = 0
        self.first = ""

    def __call__(self, data: dict[str, Any], ignore_prefix: bool = False) -> None:
        lines = [str(line) for line in data.get("lines", [])]
        if not lines:
            return
        self.count += 1
        self.first = self.first or lines[0].strip()
        with open(log_path(), "a") as log:
            log.write(f"({data.get('pid', '')}) " + "\n".join(lines) + "\n")


@contextlib.contextmanager
def session(options: RayOptions, cpus: int) -> Iterator[Any]:
    """Ray, connected (unless it is already) for the block, and shut down after it if this
    block started it; Ray's driver messages meanwhile go to :func:`log_path`, with one note at
    the end if there were any."""
    try:
        import ray
    except ImportError as exc:
        raise ImportError("the ray backend needs Ray: install vlb-gym[ray]") from exc
    from ray._private import worker

    ours = not ray.is_initialized()
    if ours:
        try:
            connect(ray, options, cpus)
        except BaseException:
            _drop_empty_log()
            raise
    messages = _Messages()
    printer, worker.print_to_stdstream = worker.print_to_stdstream, messages
    try:
        yield ray
    finally:
        worker.print_to_stdstream = printer
        if ours:
            with _stderr_to(log_path()):
                ray.shutdown()
        if messages.count:
            NOTES.warning(f"Ray reported {messages.count} event(s), e.g. "
                          f"'{messages.first[:120]}'; all in {log_path()}")
        _drop_empty_log()
