"""What the primitives of the simulated scenes share: the checks of their parameters,
the least ray parameter of a hit, and the procedural texture of the table and boxes.

The primitives (:mod:`robostereo.simulation.primitives`,
:mod:`robostereo.simulation.targets`) are frozen dataclasses that validate themselves
with :func:`xy_pair` and :func:`require_albedo` and count a ray's intersection as a hit
only beyond :data:`HIT_EPS` of its origin.  :class:`NoiseTexture` modulates the albedo
(grey reflectance) of a :class:`~robostereo.simulation.primitives.TablePlane` or a
:class:`~robostereo.simulation.primitives.Box` by world ``(x, y)``, millimetres.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import gaussian_filter

from robostereo.errors import InputError, require_finite, require_positive

__all__ = [
    "NoiseTexture",
    "require_albedo",
    "xy_pair",
]

#: the least ray parameter of a hit: nearer intersections are not in front of the origin
HIT_EPS = 1e-9
_Arr = NDArray[np.float64]


def require_albedo(albedo: float) -> None:
    """Refuse an `albedo` (grey reflectance) that is not a finite number in ``[0, 1]``.

    Raises
    ------
    InputError
        A NaN or infinite albedo, or one outside ``[0, 1]``.

    Examples
    --------
    >>> require_albedo(0.3)
    >>> require_albedo(1.5)
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: albedo must be in [0, 1], got 1.5
    """
    require_finite("albedo", albedo)
    if not 0.0 <= albedo <= 1.0:
        raise InputError(f"albedo must be in [0, 1], got {albedo}")


def xy_pair(name: str, value: Sequence[float]) -> tuple[float, float]:
    """`value` as a pair of finite floats ``(x, y)``; InputError (naming `name`) otherwise.

    Examples
    --------
    >>> xy_pair("center", [1, 2.5])
    (1.0, 2.5)
    """
    if len(value) != 2:
        raise InputError(f"{name} must be (x, y), got {value}")
    require_finite(name, [float(v) for v in value])
    return float(value[0]), float(value[1])


# --------------------------------------------------------------------------- texture


@dataclass(frozen=True, eq=False)
class NoiseTexture:
    """A smooth, periodic grey-level pattern for the table (procedural texture).

    The albedo at world ``(x, y)`` is multiplied by ``1 + amplitude * v(x, y)``,
    where ``v`` is the bilinear interpolation of ``values`` on a periodic grid of
    cell size ``cell_mm``.  Build one with :meth:`from_rng` so that the pattern is
    fixed when the scene is built and rendering stays deterministic.

    Parameters
    ----------
    values : ndarray, shape (n, m)
        Pattern values, scaled to ``[-1, 1]``; rows along world y, columns along x.
    cell_mm : float
        Grid spacing in millimetres.
    amplitude : float
        Relative albedo modulation, in ``[0, 1)``.
    """

    values: _Arr
    cell_mm: float = 4.0
    amplitude: float = 0.15

    def __post_init__(self) -> None:
        v = np.array(self.values, dtype=float)
        if v.ndim != 2 or min(v.shape) < 2 or not np.all(np.isfinite(v)):
            raise InputError(f"values must be a finite 2-D array of at least 2 x 2, got {v.shape}")
        v.setflags(write=False)
        object.__setattr__(self, "values", v)
        require_positive("cell_mm", self.cell_mm)
        if not 0.0 <= self.amplitude < 1.0:
            raise InputError(f"amplitude must be in [0, 1), got {self.amplitude}")

    @classmethod
    def from_rng(
        cls,
        rng: np.random.Generator,
        *,
        size: int = 64,
        cell_mm: float = 4.0,
        amplitude: float = 0.15,
        smooth_cells: float = 1.5,
    ) -> NoiseTexture:
        """Gaussian-smoothed white noise on a ``size x size`` periodic grid.

        Examples
        --------
        >>> t = NoiseTexture.from_rng(np.random.default_rng(0), size=16)
        >>> t.values.shape, float(np.abs(t.values).max())
        ((16, 16), 1.0)
        """
        if not isinstance(rng, np.random.Generator):
            raise InputError("rng must be a numpy.random.Generator")
        if int(size) != size or size < 2:
            raise InputError(f"size must be an integer >= 2, got {size}")
        noise = rng.standard_normal((int(size), int(size)))
        v = gaussian_filter(noise, smooth_cells, mode="wrap")
        v -= v.mean()
        v /= np.abs(v).max()
        return cls(v, cell_mm=cell_mm, amplitude=amplitude)

    def factor(self, x: _Arr, y: _Arr) -> _Arr:
        """Albedo factor ``1 + amplitude * v`` at world points, same shape as `x`."""
        n, m = self.values.shape
        u = np.asarray(x, dtype=float) / self.cell_mm
        w = np.asarray(y, dtype=float) / self.cell_mm
        u0 = np.floor(u)
        w0 = np.floor(w)
        fu = u - u0
        fw = w - w0
        j0 = u0.astype(np.int64) % m
        i0 = w0.astype(np.int64) % n
        j1 = (j0 + 1) % m
        i1 = (i0 + 1) % n
        v = self.values
        val = (v[i0, j0] * (1 - fu) + v[i0, j1] * fu) * (1 - fw) + (
            v[i1, j0] * (1 - fu) + v[i1, j1] * fu
        ) * fw
        return 1.0 + self.amplitude * val
