"""The ``lcpsim`` command line: :mod:`.main` builds the parser from the
registered subcommands; :mod:`.simulate` and :mod:`.experiments` register theirs.

``lcpsim`` (the console script) and ``python -m lcpsim`` call :func:`main`.
"""

from __future__ import annotations

from .main import EXIT_NOT_SOLVED, EXIT_OK, EXIT_USAGE, CliError, Command, build_parser, main, register_command

__all__ = ["main", "register_command", "Command", "CliError", "build_parser", "EXIT_OK", "EXIT_NOT_SOLVED", "EXIT_USAGE"]
