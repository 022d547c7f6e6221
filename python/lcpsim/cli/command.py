"""The ``lcpsim`` subcommands' registry and exit codes.

Each command module (:mod:`.solve`, :mod:`.simulate`, :mod:`.experiments`)
registers its subcommands with :func:`register_command`; :mod:`.main` builds
the parser from them. Any error a user can cause (missing or malformed file,
invalid option) prints one line ``lcpsim: error: …`` on stderr and exits 2.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from typing import Callable

__all__ = ["EXIT_OK", "EXIT_NOT_SOLVED", "EXIT_USAGE", "CliError", "Command", "register_command", "commands"]

#: Exit codes: solved, solved-not (the solver returned another status), user error.
EXIT_OK, EXIT_NOT_SOLVED, EXIT_USAGE = 0, 1, 2


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
