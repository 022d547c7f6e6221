"""The ``lcpsim`` command line: the parser built from the registered
subcommands (:mod:`.solve`, :mod:`.simulate`, :mod:`.experiments`), and
:func:`main`, the entry point of the ``lcpsim`` script and ``python -m lcpsim``.
"""

from __future__ import annotations

import argparse
import sys
from typing import NoReturn, Sequence

from .. import __version__
# Each registers its subcommands, in the order `lcpsim --help` lists them.
from . import solve  # noqa: F401
from . import simulate  # noqa: F401
from . import view  # noqa: F401
from . import experiments  # noqa: F401
from . import export_fclib  # noqa: F401
from .command import EXIT_INTERNAL, EXIT_NOT_SOLVED, EXIT_OK, EXIT_USAGE, CliError, Command, commands, register_command

__all__ = [
    "main",
    "build_parser",
    "register_command",
    "Command",
    "CliError",
    "EXIT_OK",
    "EXIT_NOT_SOLVED",
    "EXIT_USAGE",
    "EXIT_INTERNAL",
]


class _Parser(argparse.ArgumentParser):
    """argparse with lcpsim's error contract: one line ``lcpsim …: error: …``
    on stderr plus one hint line, exit 2 (argparse prints the whole usage)."""

    def error(self, message: str) -> "NoReturn":  # type: ignore[override]
        print(f"{self.prog}: error: {' '.join(message.split())}", file=sys.stderr)
        print(f"hint: {self.prog} --help lists the options", file=sys.stderr)
        raise SystemExit(EXIT_USAGE)


# ---------------------------------------------------------------- main


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="lcpsim",
        description="Rigid-body contact simulation with a Lemke LCP solver, and tools to study its LCPs.",
    )
    parser.add_argument("--version", action="version", version=f"lcpsim {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for cmd in commands():
        p = sub.add_parser(cmd.name, help=cmd.help, description=cmd.help)
        cmd.configure(p)
        p.set_defaults(_run=cmd.run)
    return parser


def _one_line(e: BaseException) -> str:
    msg = str(e) or type(e).__name__
    if isinstance(e, FileNotFoundError) and e.filename and e.strerror:
        msg = f"{e.filename}: {e.strerror}"
    return " ".join(msg.split())


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``lcpsim`` script; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    run = getattr(args, "_run", None)
    if run is None:  # bare `lcpsim`: the help, as a usage error
        parser.print_help(sys.stderr)
        return EXIT_USAGE
    try:
        return int(run(args))
    except (CliError, OSError, ValueError, MemoryError) as e:
        print(f"lcpsim: error: {_one_line(e)}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("lcpsim: interrupted", file=sys.stderr)
        return 130
    except Exception as e:  # a bug: one line, and an exit code no user error or solver status uses
        print(f"lcpsim: internal error (please report): {type(e).__name__}: {_one_line(e)}", file=sys.stderr)
        return EXIT_INTERNAL


if __name__ == "__main__":
    sys.exit(main())
