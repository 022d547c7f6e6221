"""Where ``World.run`` sends the LCPs it captures: a capture file
(:class:`lcpsim.CaptureWriter`), an FCLib directory
(:class:`lcpsim.fclib.FclibExporter`), or both."""

from __future__ import annotations

import os
from typing import Any, Mapping

__all__ = ["RunSinks"]


class RunSinks:
    """The writers of one ``World.run``; closes only those it opened."""

    def __init__(self, capture: Any, fclib: str | os.PathLike[str] | None, config: Mapping[str, Any]) -> None:
        from .capture import CaptureWriter

        self._sinks: list[tuple[Any, bool]] = []
        try:
            if capture is not None:
                own = not isinstance(capture, CaptureWriter)
                self._sinks.append((CaptureWriter(capture, metadata=config) if own else capture, own))
            if fclib is not None:
                from ..fclib import FclibExporter

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

    def close(self) -> None:
        for s, own in self._sinks:
            if own:
                s.close()
