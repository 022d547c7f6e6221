"""The ``lcpsim`` subcommands' registry and exit codes.

Each command module (:mod:`.solve`, :mod:`.simulate`, :mod:`.experiments`)
registers its subcommands with :func:`register_command`; :mod:`.main` builds
the parser from them.

Exit codes (every command):

=====  ==================================================================
0      done: every LCP solved, every sweep case finished
1      ran, but the solver returned another status (an LCP not solved)
       or a sweep case failed — never anything else
2      user error: missing or malformed file, invalid option or value
       (one line ``lcpsim: error: …`` on stderr; argparse adds a hint line)
3      internal error: a bug in lcpsim (one line on stderr; please report)
130    interrupted (Ctrl-C)
=====  ==================================================================
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from typing import Any, Callable

__all__ = [
    "EXIT_OK", "EXIT_NOT_SOLVED", "EXIT_USAGE", "EXIT_INTERNAL", "CliError", "Command", "register_command",
    "commands", "lemke_options",
]

#: Exit codes: solved, solved-not (the solver returned another status), user error, lcpsim bug.
EXIT_OK, EXIT_NOT_SOLVED, EXIT_USAGE, EXIT_INTERNAL = 0, 1, 2, 3


class CliError(Exception):
    """An error to report as one line on stderr (exit code 2)."""


@dataclass(frozen=True)
class Command:
    """A subcommand: ``configure`` adds its arguments, ``run`` returns the exit code."""

    name: str
    help: str
    configure: Callable[[argparse.ArgumentParser], None]
    run: Callable[[argparse.Namespace], int]


_COMMANDS: dict[str, Command] = {}


def register_command(command: Command) -> Command:
    """Adds a subcommand (replacing one of the same name)."""
    _COMMANDS[command.name] = command
    return command


def commands() -> list[Command]:
    """The registered subcommands, in registration order."""
    return list(_COMMANDS.values())


def lemke_options(args: argparse.Namespace, method: str) -> dict[str, Any]:
    """The Lemke options given on the command line (``--pivoting``, ``--piv-tol``,
    ``--zero-tol``, ``--max-pivots``; only those given). With another method they
    are an error, as ``solve_lcp`` makes them."""
    given = {
        k: getattr(args, k, None) for k in ("pivoting", "piv_tol", "zero_tol", "max_pivots")
        if getattr(args, k, None) is not None
    }
    if given and method != "lemke":
        raise CliError(f"--{next(iter(given)).replace('_', '-')} applies only to --method lemke, not {method}")
    return given
