"""Where ``World.run`` sends the LCPs it captures: a capture file
(:class:`lcpsim.CaptureWriter`), an FCLib directory
(:class:`lcpsim.faceting.FclibExporter`), or both."""

from __future__ import annotations

import os
from typing import Any, Mapping

__all__ = ["RunSinks"]


class RunSinks:
    """The writers of one ``World.run``; closes only those it opened."""

    def __init__(
        self, capture: Any, fclib: str | os.PathLike[str] | None, config: Mapping[str, Any], *, overwrite: bool = False
    ) -> None:
        from .capture import CaptureWriter

        self._sinks: list[tuple[Any, bool]] = []
        try:
            if capture is not None:
                own = not isinstance(capture, CaptureWriter)
                writer = CaptureWriter(capture, metadata=config, overwrite=overwrite) if own else capture
                self._sinks.append((writer, own))
            if fclib is not None:
                from ..faceting import FclibExporter

                if int(config.get("params", {}).get("friction_dirs", 8)) < 3:
                    raise ValueError("fclib export needs friction_dirs >= 3 (both tangent directions)")
                self._sinks.append((FclibExporter(fclib, config), True))
        except BaseException:
            self.close()
            raise

    def __bool__(self) -> bool:
        return bool(self._sinks)

    def begin_run(self, config: Mapping[str, Any]) -> None:
        for s, _ in self._sinks:
            s.begin_run(config)

    def append(self, captured: Mapping[str, Any]) -> None:
        for s, _ in self._sinks:
            s.append(captured)

    def flush(self) -> None:
        for s, _ in self._sinks:
            s.flush()

    def close(self, *, complete: bool = True) -> None:
        """Closes the writers it opened; a capture of an interrupted run
        (``complete=False``) stays ``PATH.partial``."""
        from .capture import CaptureWriter

        for s, own in self._sinks:
            if own and isinstance(s, CaptureWriter):
                s.close(complete=complete)
            elif own:
                s.close()
