"""Shared test helpers: run the CLI in-process and capture its exit code and streams."""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path

import pytest

from voidcross.cli import main


def pytest_configure(config):
    """One fresh user cache per test session (solves, launch allowances, FE and capture results):
    tests never read a developer's cache (a stale entry would hide a regression) nor write into
    it, yet share the solves they repeat. The session's controller makes it and every xdist
    worker inherits it (``VOIDCROSS_TEST_CACHE``), so a solve one worker made is a hit in the
    other (the caches are safe across processes: SQLite in WAL mode, files written atomically).
    Set through ``os.environ`` so CLI subprocesses inherit it. A test about a cold cache sets
    its own ``XDG_CACHE_HOME``."""
    if os.environ.get("VOIDCROSS_TEST_KEEP_CACHE"):
        return
    inherited = os.environ.get("VOIDCROSS_TEST_CACHE")
    if hasattr(config, "workerinput") and inherited and os.path.isdir(inherited):
        os.environ["XDG_CACHE_HOME"] = inherited  # the controller owns (and removes) it
        return
    d = tempfile.mkdtemp(prefix="voidcross-test-cache-")
    config._voidcross_cache = d
    os.environ["XDG_CACHE_HOME"] = d
    os.environ["VOIDCROSS_TEST_CACHE"] = d


#: Files whose tests share no module-scoped fixture and together cost minutes: xdist spreads them
#: test by test over the workers. Every other file stays whole on one worker (``xdist_group`` by
#: file, ``make test`` runs ``--dist loadgroup``), so its module fixtures are built once.
SPREAD = ("tests/structure_fem/test_never_crash.py",)


#: Files that read the session's CAD export (``export_dir`` is the cad pipeline stage's export,
#: ``tests/cubot_cad/conftest.py``) run as one group on one worker: the other worker never waits on
#: the stage's lock, and the robots and docked pairs the stage builds in that process (OCC shapes,
#: cached per process) are the ones these files use.
GROUPS = {f"tests/cubot_cad/{name}.py": "tests/cubot_cad (the session's export)"
          for name in ("test_cad_cli", "test_check", "test_export", "test_glb", "test_pier", "test_rail",
                       "test_slicing")}


def pytest_itemcollected(item):
    """The file's group (or its entry in :data:`GROUPS`), set as each item is collected: xdist reads
    the groups into the node ids in its own ``pytest_collection_modifyitems``, which ran before this
    conftest's (so the groups were never seen and module fixtures were built once per worker)."""
    rel = Path(str(item.path)).relative_to(Path(str(item.config.rootpath))).as_posix()
    if rel not in SPREAD:
        item.add_marker(pytest.mark.xdist_group(GROUPS.get(rel, rel)))


def pytest_unconfigure(config):
    d = getattr(config, "_voidcross_cache", None)
    if d:
        shutil.rmtree(d, ignore_errors=True)
        os.environ.pop("VOIDCROSS_TEST_CACHE", None)


def shared_once(name: str, build) -> Path:
    """A directory built once per test session for every xdist worker: ``build(path)`` fills
    ``path`` in the first worker that asks; the others wait on the lock, then read the same
    directory (expensive results a test is not about: a CAD export, the cad pipeline stage).
    Callers treat it as read-only. Outside a session cache (``VOIDCROSS_TEST_KEEP_CACHE``) it is
    a fresh directory per process. A build that raises leaves nothing behind: the next asker
    builds again (and fails the same way, in its own test)."""
    import fcntl

    root = os.environ.get("VOIDCROSS_TEST_CACHE") or tempfile.mkdtemp(prefix="voidcross-test-once-")
    base = Path(root) / "once"
    base.mkdir(parents=True, exist_ok=True)
    final = base / name
    with open(base / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file closes (also if this worker dies)
        if not (final / ".done").exists():
            shutil.rmtree(final, ignore_errors=True)  # a build cut short (no .done) starts again
            final.mkdir()
            try:
                build(final)  # in place: paths the build records stay valid
            except BaseException:
                shutil.rmtree(final, ignore_errors=True)
                raise
            (final / ".done").touch()
    return final


@pytest.fixture(scope="session")
def once():
    """:func:`shared_once` as a fixture: ``once("name", build) -> Path``."""
    return shared_once


class CliResult:
    def __init__(self, code: int, out: str, err: str):
        self.code, self.out, self.err = code, out, err

    def json(self):
        return json.loads(self.out)

    @property
    def error_lines(self) -> list[str]:
        return [ln for ln in self.err.splitlines() if ln.strip()]


@pytest.fixture
def cli(capsys):
    """``cli("fem", "table", "--json") -> CliResult`` (SystemExit from argparse is caught)."""

    def run(*argv: str) -> CliResult:
        try:
            code = main(list(argv))
        except SystemExit as exc:  # argparse --help / usage errors
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
        captured = capsys.readouterr()
        return CliResult(code, captured.out, captured.err)

    return run


def _in_ci() -> bool:
    return os.environ.get("CI", "").strip().lower() in ("1", "true", "yes")


@pytest.fixture
def require_tool():
    """``require_tool(path_or_None, "prusa-slicer")``: a test whose real client is missing is
    skipped on a developer's machine but FAILS in CI (``CI=true``), where ``make test`` must
    have installed it (Makefile target ``clients``)."""

    def need(path, what: str):
        if path is None:
            msg = f"{what} is not installed (make test installs it from Debian's packages when root with apt)"
            if _in_ci():
                pytest.fail(msg + "; in CI that is a set-up failure, not a skip")
            pytest.skip(msg)
        return path

    return need
