"""What every contact LCP type with a known contact count ``nc`` and ``k``
friction directions per contact shares (:class:`lcpsim.examples.ContactLcp`,
:class:`lcpsim.faceting.FacetedLcp`): its :class:`~lcpsim.ContactLayout` and the
split of an answer ``z = [fn; fd; λ]``."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._core import ContactLayout

__all__ = ["ContactLcpMixin"]


class ContactLcpMixin:
    """``layout`` and ``split`` for a (data)class with fields ``nc`` and ``k``."""

    nc: int
    k: int

    @property
    def layout(self) -> ContactLayout:
        """Where fn, fd, λ live in ``z``."""
        return ContactLayout(self.nc, self.k)

    def split(self, z: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """``(fn, fd, λ)`` of a solution ``z``; ``fd`` has shape (nc, k)."""
        zz = np.asarray(z, dtype=np.float64)
        lay = self.layout
        return zz[lay.fn], zz[lay.fd].reshape(lay.nc, lay.k), zz[lay.lam]
