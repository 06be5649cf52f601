"""Where sweep runs execute: a local process pool (default) or a Dask cluster.

An executor takes ``(run_fn, keys)`` and yields ``(key, outcome)`` pairs in
completion order, with at most ``window`` runs in flight, so a sweep of a
million runs holds only a few futures and Ctrl-C stops promptly. The
outcome is produced in the worker by :func:`execute_run`: ``{"status": "ok",
"result": dict}`` or ``{"status": "error", "error_type", "error"
(traceback)}``, plus ``wall_s`` and ``worker``. Only the parent process
writes to the database.
"""

from __future__ import annotations

import concurrent.futures as cf
import importlib
import logging
import multiprocessing
import os
import signal
import time
import traceback
from collections.abc import Callable, Iterable, Iterator

from ..errors import InputError
from .store import worker_id

RunFn = Callable[[dict], dict]


def resolve_run_fn(ref: str | RunFn) -> RunFn:
    """A callable, or ``"package.module:function"``."""
    if callable(ref):
        return ref
    mod, sep, name = str(ref).partition(":")
    if not sep or not mod or not name:
        raise InputError(f"--run-fn {ref!r}: expected 'package.module:function'")
    try:
        fn = getattr(importlib.import_module(mod), name)
    except (ImportError, AttributeError) as exc:
        raise InputError(f"--run-fn {ref!r}: cannot import ({exc})") from None
    if not callable(fn):
        raise InputError(f"--run-fn {ref!r}: {name} is not callable")
    return fn


def execute_run(run_fn: RunFn | str, key: dict) -> dict:
    """Run one key in a worker; never raises for an ``Exception`` of the run."""
    t0 = time.perf_counter()
    try:
        result = resolve_run_fn(run_fn)(key)
        if hasattr(result, "to_dict"):
            result = result.to_dict()
        if not isinstance(result, dict):
            raise TypeError(f"run function returned {type(result).__name__}, expected a dict")
        return {"status": "ok", "result": result, "wall_s": time.perf_counter() - t0, "worker": worker_id()}
    except Exception as exc:  # recorded with its traceback; the sweep goes on
        return {"status": "error", "error_type": f"{type(exc).__module__}.{type(exc).__qualname__}",
                "error": traceback.format_exc(), "wall_s": time.perf_counter() - t0, "worker": worker_id()}


def execute_batch(run_fn: RunFn | str, keys: list[dict]) -> list[dict]:
    """Run a batch of keys in one task (one round trip and one pickled run function per batch,
    not per run); outcomes in key order, each as :func:`execute_run` gives it."""
    fn = resolve_run_fn(run_fn)
    return [execute_run(fn, k) for k in keys]


#: runs per task handed to a worker: few enough that Ctrl-C loses at most a few runs per worker
DEFAULT_BATCH = 4


def _batches(keys: Iterable[dict], size: int) -> Iterator[list[dict]]:
    it = iter(keys)
    while batch := [k for _, k in zip(range(size), it, strict=False)]:
        yield batch


def _worker_init() -> None:
    """Workers ignore Ctrl-C (the parent handles it) and die with the parent (Linux)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        import ctypes

        libc = ctypes.CDLL("libc.so.6", use_errno=True)
        libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG: no orphans after kill -9 of the sweep
        if os.getppid() == 1:  # parent already gone
            os._exit(1)
    except (OSError, AttributeError):  # pragma: no cover - not Linux
        pass


#: One math-library thread per worker process: N single-run workers on N cores, not N x N
#: threads fighting for them (Dask's nanny sets the same for its workers).
SINGLE_THREAD_ENV = {k: "1" for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                                      "NUMEXPR_NUM_THREADS", "NUMBA_NUM_THREADS")}


class LocalExecutor:
    """A process pool on this machine (``spawn``: workers import a clean interpreter), one
    math-library thread per worker unless the caller's environment sets otherwise."""

    name = "local"

    def __init__(self, workers: int | None = None, batch: int = DEFAULT_BATCH):
        n = workers or os.cpu_count() or 1
        if n < 1:
            raise InputError(f"--workers {workers}: must be >= 1")
        self.workers = n
        self.batch = _check_batch(batch)
        self._pool: cf.ProcessPoolExecutor | None = None

    def __enter__(self):
        # workers are spawned lazily and inherit os.environ at spawn time: keep it set while open
        self._saved_env = {k: os.environ.get(k) for k in SINGLE_THREAD_ENV}
        for k, v in SINGLE_THREAD_ENV.items():
            os.environ.setdefault(k, v)
        self._pool = cf.ProcessPoolExecutor(
            max_workers=self.workers, mp_context=multiprocessing.get_context("spawn"),
            initializer=_worker_init)
        return self

    def __exit__(self, exc_type, exc, tb):
        self.close(cancel=exc_type is not None)

    def close(self, cancel: bool = False) -> None:
        pool, self._pool = self._pool, None
        if pool is None:
            return
        try:
            self._shutdown(pool, cancel)
        finally:
            for k, v in getattr(self, "_saved_env", {}).items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v

    @staticmethod
    def _shutdown(pool, cancel: bool) -> None:
        if cancel:
            procs = list((getattr(pool, "_processes", None) or {}).values())
            pool.shutdown(wait=False, cancel_futures=True)
            for p in procs:  # do not wait for runs that are being thrown away
                if p.is_alive():
                    p.terminate()
            for p in procs:
                p.join(timeout=5)
        else:
            pool.shutdown(wait=True)

    def run(self, run_fn: RunFn | str, keys: Iterable[dict], window: int | None = None
            ) -> Iterator[tuple[dict, dict]]:
        assert self._pool is not None, "use LocalExecutor as a context manager"
        window = window or 2 * self.workers  # batches in flight
        it = _batches(keys, self.batch)
        inflight: dict[cf.Future, list[dict]] = {}

        def fill():
            while len(inflight) < window:
                b = next(it, None)
                if b is None:
                    return
                inflight[self._pool.submit(execute_batch, run_fn, b)] = b

        fill()
        while inflight:
            done, _ = cf.wait(inflight, return_when=cf.FIRST_COMPLETED)
            for fut in done:
                batch = inflight.pop(fut)
                yield from zip(batch, fut.result(), strict=True)  # BrokenProcessPool propagates
            fill()


class DaskExecutor:
    """Dask distributed: connect to ``address`` (``tcp://host:8786``), or start a
    :class:`distributed.LocalCluster` of ``workers`` single-threaded processes on loopback."""

    name = "dask"

    def __init__(self, address: str | None = None, workers: int | None = None, processes: bool = True,
                 batch: int = DEFAULT_BATCH):
        self.batch = _check_batch(batch)
        try:
            import distributed  # noqa: F401
        except ImportError:
            raise InputError("--executor dask needs dask[distributed] (pip install 'voidcross[dist]')") from None
        self.address, self.workers, self.processes = address, workers, processes
        self.client = None
        self.cluster = None

    def __enter__(self):
        from distributed import Client, LocalCluster

        if self.address:
            try:
                self.client = Client(self.address, timeout="10s")
            except (OSError, TimeoutError) as exc:
                raise InputError(f"--address {self.address}: cannot reach a Dask scheduler ({exc})") from None
        else:
            self.cluster = LocalCluster(
                n_workers=self.workers or os.cpu_count() or 1, threads_per_worker=1,
                processes=self.processes, protocol="tcp://", host="127.0.0.1", dashboard_address=None,
                silence_logs=logging.ERROR)
            self.client = Client(self.cluster)
        self.workers = len(self.client.scheduler_info().get("workers", {})) or self.workers
        return self

    def __exit__(self, exc_type, exc, tb):
        self.close()

    def close(self, cancel: bool = False) -> None:
        if self.client is not None:
            self.client.close()
            self.client = None
        if self.cluster is not None:
            self.cluster.close()
            self.cluster = None

    def run(self, run_fn: RunFn | str, keys: Iterable[dict], window: int | None = None
            ) -> Iterator[tuple[dict, dict]]:
        from distributed import as_completed

        assert self.client is not None, "use DaskExecutor as a context manager"
        window = window or 4 * max(1, self.workers or 1)  # batches in flight: workers fed across round trips
        it = _batches(keys, self.batch)
        inflight: dict = {}

        def submit(b):
            fut = self.client.submit(execute_batch, run_fn, b, pure=False)
            inflight[fut] = b
            return fut

        first = []
        for _ in range(window):
            b = next(it, None)
            if b is None:
                break
            first.append(submit(b))
        ac = as_completed(first)
        try:
            for fut in ac:
                batch = inflight.pop(fut)
                outcomes = fut.result()
                fut.release()
                yield from zip(batch, outcomes, strict=True)
                b = next(it, None)
                if b is not None:
                    ac.add(submit(b))
        finally:
            if inflight:
                self.client.cancel(list(inflight))


class SerialExecutor:
    """Runs keys one after another in this process (library use: debugging, tests, tiny sweeps)."""

    name = "serial"
    workers = 1

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return None

    def close(self, cancel: bool = False) -> None:
        return None

    def run(self, run_fn: RunFn | str, keys: Iterable[dict], window: int | None = None
            ) -> Iterator[tuple[dict, dict]]:
        fn = resolve_run_fn(run_fn)
        for k in keys:
            yield k, execute_run(fn, k)


def _check_batch(batch) -> int:
    if isinstance(batch, bool) or not isinstance(batch, int) or not 1 <= batch <= 10_000:
        raise InputError(f"--batch {batch!r}: runs per worker task must be an integer in 1..10000")
    return batch


def make_executor(kind: str = "local", workers: int | None = None, address: str | None = None,
                  batch: int = DEFAULT_BATCH):
    """``batch``: runs handed to a worker per task (local and dask)."""
    if kind == "local":
        if address:
            raise InputError(f"--address {address}: only meaningful with --executor dask")
        return LocalExecutor(workers, batch=batch)
    if kind == "dask":
        return DaskExecutor(address=address, workers=workers, batch=batch)
    if kind == "serial":
        return SerialExecutor()
    raise InputError(f"--executor {kind!r}: choose local or dask")
