"""Old names kept working: modules that moved into a sub-package, and
renamed functions or classes. Each use emits a :class:`DeprecationWarning`
naming the new home; nothing else changes (the alias *is* the new object).

This is the one place deprecated aliases are declared; a module with renamed
names sets ``__getattr__ = deprecated_names(__name__, {...})``.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import warnings
from types import ModuleType
from typing import Any, Callable, Mapping, Sequence

#: Old module → its new home.
MOVED_MODULES: dict[str, str] = {
    "lcpsim.corpus": "lcpsim.io.capture",
    "lcpsim.forensics": "lcpsim.io.forensics",
    "lcpsim.cli_simulate": "lcpsim.cli.simulate",
    "lcpsim.cli_experiments": "lcpsim.cli.experiments",
}


def warn(old: str, new: str) -> None:
    warnings.warn(f"{old} is deprecated; use {new}", DeprecationWarning, stacklevel=3)


class _Alias(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Imports a moved module under its old name: ``import lcpsim.corpus``
    gives the module ``lcpsim.io.capture`` itself."""

    def find_spec(
        self, fullname: str, path: Sequence[str] | None = None, target: ModuleType | None = None
    ) -> importlib.machinery.ModuleSpec | None:
        if fullname not in MOVED_MODULES:
            return None
        return importlib.machinery.ModuleSpec(fullname, self)

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> ModuleType:
        new = MOVED_MODULES[spec.name]
        warn(f"module {spec.name}", new)
        return importlib.import_module(new)

    def exec_module(self, module: ModuleType) -> None:
        """The new module is already executed."""


def install() -> None:
    """Adds the old module names to the import system (once)."""
    if not any(isinstance(f, _Alias) for f in sys.meta_path):
        sys.meta_path.append(_Alias())


def moved_module(package: str, name: str) -> ModuleType | None:
    """The moved module ``package.name`` (imported under its old name), or None."""
    old = f"{package}.{name}"
    if old not in MOVED_MODULES:
        return None
    return importlib.import_module(old)


def deprecated_names(module: str, aliases: Mapping[str, tuple[str, Callable[[], Any]]]) -> Callable[[str], Any]:
    """A module ``__getattr__`` serving ``aliases``: old name → (new name, getter)."""

    def __getattr__(name: str) -> Any:
        if name in aliases:
            new, get = aliases[name]
            warn(f"{module}.{name}", new)
            return get()
        moved = moved_module(module, name)
        if moved is not None:
            return moved
        raise AttributeError(f"module {module!r} has no attribute {name!r}")

    return __getattr__
