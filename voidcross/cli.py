"""The `voidcross` command line.

One argparse tree; each sub-command lives in ``voidcross/commands/<name>.py``
and exposes ``register(subparsers, common)``, which adds its parser and sets
``func(args) -> int``. The contract every command keeps:

* exit 0 on success;
* exit 2 on bad input, with one line ``error: ...`` naming the bad value
  (any :class:`cubot_cad.errors.InputError`, and argparse's own errors);
* exit 1 on an internal failure, the traceback shown only with ``--debug``;
* ``--json`` prints machine-readable results on stdout, human text otherwise;
  progress bars go to stderr.
"""

from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys
import threading
import traceback

from cubot_cad.errors import InputError

COMMANDS = ("cad", "fem", "sim", "sweep", "reproduce", "optimise", "report", "pipeline", "doctor")

EPILOG = """examples:
  voidcross doctor                      what is installed and what it enables
  voidcross pipeline                    CAD export, structure table, simulations, report
  voidcross cad export --robot cubot    printable STL/STEP + manifest into exports/
  voidcross fem table --json            derived structure thresholds next to the thesis's
  voidcross sim run --preset case-d --robots 9 --void-width 2 --seed 1 --json
  voidcross sweep --preset case-d --robots 3-12 --void-width 1-3 --runs 5 --db results/d.sqlite
  voidcross optimise --cases a,b,c,d --trials 30 --db results/opt.sqlite --report
  voidcross report --db results/d.sqlite --out report/
"""


class OneLineErrorParser(argparse.ArgumentParser):
    """argparse that reports usage errors as one ``error: ...`` line, exit 2."""

    def error(self, message: str):  # noqa: D102 - argparse API
        self.exit(2, f"error: {self.prog}: {message} (see {self.prog} --help)\n")


def common_options() -> argparse.ArgumentParser:
    """Options every sub-command accepts (after the sub-command name too)."""
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--json", action="store_true", default=argparse.SUPPRESS,
                        help="print machine-readable JSON on stdout")
    common.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                        help="show tracebacks of internal failures; run invariant checks")
    return common


def build_parser() -> argparse.ArgumentParser:
    common = common_options()
    parser = OneLineErrorParser(
        prog="voidcross",
        description="Self-assembling swarm-robot bridges: robot CAD (mm), structure mechanics (SI), "
                    "swarm simulation (cm, s), sweeps and reports.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
        parents=[common],
    )
    from . import __version__

    parser.add_argument("--version", action="version", version=f"voidcross {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=OneLineErrorParser)
    for name in COMMANDS:
        module = importlib.import_module(f"voidcross.commands.{name}")
        module.register(sub, common)
    return parser


def main(argv: list[str] | None = None) -> int:
    from .output import refuse_empty_values

    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        refuse_empty_values(argv)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    parser = build_parser()
    args = parser.parse_args(argv)
    args.json = getattr(args, "json", False)
    args.debug = getattr(args, "debug", False) or bool(os.environ.get("VOIDCROSS_DEBUG"))
    func = getattr(args, "func", None)
    if func is None:
        parser.print_help()
        return 0
    if threading.current_thread() is threading.main_thread():
        # Ctrl-C always interrupts (and long commands store what finished): a process started in
        # the background by a non-interactive shell inherits SIGINT ignored, and Python keeps that
        signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        return int(func(args) or 0)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("error: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0
    except Exception as exc:  # internal failure: exit 1, traceback only with --debug
        if args.debug:
            traceback.print_exc()
        print(f"error: internal failure in `voidcross {args.command}`: {type(exc).__name__}: {exc}"
              + ("" if args.debug else " (re-run with --debug for the traceback)"), file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
