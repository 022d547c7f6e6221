"""The ``lcpsim`` command line. :mod:`.command` holds the subcommand registry,
:mod:`.solve`, :mod:`.simulate` and :mod:`.experiments` register theirs,
:mod:`.main` builds the parser from them.

``lcpsim`` (the console script) and ``python -m lcpsim`` call :func:`main`.
"""

from __future__ import annotations

from .command import EXIT_INTERNAL, EXIT_NOT_SOLVED, EXIT_OK, EXIT_USAGE, CliError, Command, register_command
from .main import build_parser, main

__all__ = [
    "main",
    "register_command",
    "Command",
    "CliError",
    "build_parser",
    "EXIT_OK",
    "EXIT_NOT_SOLVED",
    "EXIT_USAGE",
    "EXIT_INTERNAL",
]
