"""A ROS transform tree (``/tf``, ``/tf_static``) and the pose of one frame in another.

ROS publishes each frame's pose in its parent's as ``geometry_msgs/TransformStamped``
(``header.frame_id`` the parent, ``child_frame_id`` the child, translation in metres,
rotation a unit quaternion ``(x, y, z, w)``) in ``tf2_msgs/TFMessage`` on ``/tf``
(stamped, at the rate of the joint states) and ``/tf_static`` (fixed: a camera's mount,
a hand-eye calibration).  :class:`TransformTree` holds them, in millimetres;
:meth:`TransformTree.chain_poses` composes ``T_base_frame`` at given stamps through the
tree, as ``tf2``'s ``lookupTransform`` does:

* static edges are constant (the last one published wins);
* a dynamic edge is interpolated between the two samples around the stamp, the
  translation linearly and the rotation by spherical linear interpolation
  (:class:`scipy.spatial.transform.Slerp`);
* a stamp outside a dynamic edge's samples is refused (no extrapolation), unless it
  lies within :data:`TF_TOLERANCE_S` of the first or last, where that sample is held.

Frame names are compared without a leading ``/`` (ROS 1's ``/base_link`` is
``base_link``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation, Slerp

from robostereo.errors import InputError
from robostereo.geometry.poses import SE3

__all__ = ["TF_TOLERANCE_S", "EdgeSamples", "TransformTree", "frame_name"]

TF_TOLERANCE_S = 0.01
"""How far, seconds, a stamp may lie before the first or after the last sample of a
dynamic transform for that sample to be held (a camera and the arm's joint states are
stamped by different clocks and drivers; 10 ms is a few joint-state periods and moves
an arm at 0.1 m/s by 1 mm).  Farther is refused: ``tf2`` does not extrapolate either."""

_NS = 1_000_000_000


def frame_name(name: str) -> str:
    """A frame id without its leading ``/`` (ROS 1 wrote ``/base_link``).

    >>> frame_name("/base_link"), frame_name("tool0")
    ('base_link', 'tool0')
    """
    return str(name).strip().lstrip("/")


@dataclass(frozen=True, eq=False)
class EdgeSamples:
    """The samples of one edge of the tree, parent to child.

    Attributes
    ----------
    parent, child : str
    stamps_ns : ndarray of int64, shape (M,)
        Increasing, nanoseconds; one entry (stamp 0) for a static edge.
    translations_mm : ndarray, shape (M, 3)
        The child's origin in the parent's frame, mm.
    rotations : Rotation
        ``M`` rotations, the child's axes in the parent's frame.
    static : bool
    """

    parent: str
    child: str
    stamps_ns: NDArray[np.int64]
    translations_mm: NDArray[np.float64]
    rotations: Rotation
    static: bool = False

    def at(self, stamps_ns: NDArray[np.int64], tolerance_s: float = TF_TOLERANCE_S
           ) -> tuple[NDArray[np.float64], Rotation]:
        """Translations ``(S, 3)`` (mm) and rotations of the edge at `stamps_ns` ``(S,)``.

        Raises
        ------
        InputError
            A stamp before the first sample or after the last by more than
            `tolerance_s`, naming the two frames.
        """
        t = np.asarray(stamps_ns, dtype=np.int64)
        if self.static:
            return (np.repeat(self.translations_mm[:1], len(t), axis=0),
                    Rotation.concatenate([self.rotations[0]] * len(t)))
        s = self.stamps_ns
        tol = round(tolerance_s * _NS)
        bad = (t < s[0] - tol) | (t > s[-1] + tol)
        if bad.any():
            raise InputError(
                f"the image at {t[bad][0] / _NS:.6f} s lies outside the tf from "
                f"'{self.parent}' to '{self.child}' ({s[0] / _NS:.6f} .. {s[-1] / _NS:.6f} s;"
                f" no extrapolation past {tolerance_s:g} s)")
        held = np.clip(t, s[0], s[-1])
        if len(s) == 1:
            return (np.repeat(self.translations_mm, len(t), axis=0),
                    Rotation.concatenate([self.rotations[0]] * len(t)))
        rel = (held - s[0]).astype(np.float64) / _NS  # seconds: exact to the nanosecond
        times = (s - s[0]).astype(np.float64) / _NS
        xyz = np.column_stack([np.interp(rel, times, self.translations_mm[:, k])
                               for k in range(3)])
        return xyz, Slerp(times, self.rotations)(rel)


@dataclass(frozen=True, eq=False)
class TransformTree:
    """The edges of ``/tf`` and ``/tf_static``, each child's to its parent.

    Attributes
    ----------
    edges : dict of str to EdgeSamples
        Per child frame, its edge.
    conflicts : dict of str to str
        Child frames published under two parents (or both static and dynamic), with
        what was seen; refused when a chain goes through them.
    """

    edges: dict[str, EdgeSamples]
    conflicts: dict[str, str] = field(default_factory=dict)

    @classmethod
    def from_transforms(
        cls, transforms: Sequence[tuple[int, str, str, Sequence[float], Sequence[float],
                                        bool]], *, unit_to_mm: float = 1000.0,
    ) -> TransformTree:
        """The tree of ``(stamp_ns, parent, child, translation, quaternion_xyzw,
        static)`` tuples, translations in metres (`unit_to_mm` per unit).

        Repeated stamps of a dynamic edge keep the last sample; a static edge keeps its
        last message.  Quaternions are normalised; a zero or non-finite one is refused.
        """
        groups: dict[tuple[str, str, bool], list[tuple[int, list[float], list[float]]]] = {}
        for stamp, parent, child, xyz, q, static in transforms:
            key = (frame_name(parent), frame_name(child), bool(static))
            groups.setdefault(key, []).append((int(stamp), list(xyz), list(q)))
        edges: dict[str, EdgeSamples] = {}
        conflicts: dict[str, str] = {}
        for (parent, child, static), rows in groups.items():
            if child in edges or child in conflicts:
                first = edges.pop(child, None)
                seen = conflicts.get(child) or (
                    f"'{first.parent}' ({'static' if first.static else 'dynamic'})"
                    if first is not None else "")
                conflicts[child] = (f"{seen} and '{parent}' "
                                    f"({'static' if static else 'dynamic'})")
                continue
            if static:
                rows = rows[-1:]
            rows.sort(key=lambda r: r[0])
            stamps = np.array([r[0] for r in rows], dtype=np.int64)
            keep = np.r_[stamps[1:] != stamps[:-1], True]  # the last of equal stamps
            xyz = np.array([r[1] for r in rows], dtype=float)[keep] * unit_to_mm
            quat = np.array([r[2] for r in rows], dtype=float)[keep]
            norms = np.linalg.norm(quat, axis=1)
            if not (np.all(np.isfinite(xyz)) and np.all(np.isfinite(norms))
                    and np.all(norms > 0.5)):
                raise InputError(f"the tf from '{parent}' to '{child}' has a transform "
                                 "that is not finite or a quaternion that is not a unit one")
            edges[child] = EdgeSamples(parent, child, np.zeros(1, np.int64) if static
                                       else stamps[keep], xyz,
                                       Rotation.from_quat(quat / norms[:, None]), static)
        return cls(edges, conflicts)

    @property
    def frames(self) -> list[str]:
        """Every frame named, sorted."""
        return sorted({e.parent for e in self.edges.values()} | set(self.edges)
                      | set(self.conflicts))

    def _up(self, frame: str) -> list[str]:
        """`frame` and its ancestors, up to the root."""
        out = [frame]
        while out[-1] in self.edges:
            parent = self.edges[out[-1]].parent
            if parent in out:
                raise InputError(f"the tf tree has a loop through '{parent}'")
            out.append(parent)
        return out

    def chain(self, base: str, frame: str) -> tuple[list[str], list[str]]:
        """The frames from the common ancestor down to `base` and down to `frame`
        (each list without the ancestor, nearest it first).

        Raises
        ------
        InputError
            No chain (the two in separate trees, or a frame not in the bag), naming
            both frames; a chain through a frame published under two parents.
        """
        base, frame = frame_name(base), frame_name(frame)
        known = self.frames
        for f in (base, frame):
            if f not in known:
                listed = ", ".join(known[:12]) + (", ..." if len(known) > 12 else "")
                raise InputError(f"no tf chain from '{base}' to '{frame}': no frame '{f}' "
                                 f"in /tf or /tf_static (frames: {listed or 'none'})")
        up_b, up_f = self._up(base), self._up(frame)
        common = next((f for f in up_f if f in up_b), None)
        if common is None:
            for f in (up_b[-1], up_f[-1]):  # a frame of two parents has no edge: a root
                if f in self.conflicts:
                    raise InputError(f"the tf chain from '{base}' to '{frame}' goes through "
                                     f"'{f}', published under {self.conflicts[f]}")
            raise InputError(f"no tf chain from '{base}' to '{frame}': they are in "
                             f"separate trees (roots '{up_b[-1]}' and '{up_f[-1]}')")
        return up_b[: up_b.index(common)][::-1], up_f[: up_f.index(common)][::-1]

    def _down(self, frames: list[str], stamps_ns: NDArray[np.int64], tolerance_s: float
              ) -> tuple[NDArray[np.float64], Rotation]:
        """``T_ancestor_last`` at each stamp, composed along `frames`."""
        t = np.zeros((len(stamps_ns), 3))
        r = Rotation.identity(len(stamps_ns))
        for f in frames:
            xyz, rot = self.edges[f].at(stamps_ns, tolerance_s)
            t = t + r.apply(xyz)
            r = r * rot
        return t, r

    def chain_poses(self, base: str, frame: str, stamps_ns: Sequence[int] | NDArray[np.int64],
                    *, tolerance_s: float = TF_TOLERANCE_S) -> list[SE3]:
        """``T_base_frame`` at each stamp, millimetres.

        Parameters
        ----------
        base, frame : str
            Frame ids (a leading ``/`` ignored).
        stamps_ns : sequence of int, shape (S,)
            Nanoseconds since the epoch of the bag's clock.
        tolerance_s : float
            :data:`TF_TOLERANCE_S`.

        Returns
        -------
        list of SE3
            One per stamp.

        Notes
        -----
        1. Walk both frames up to their nearest common ancestor ``A``
           (:meth:`chain`).
        2. Compose ``T_A_base`` and ``T_A_frame`` down the edges, each edge at every
           stamp at once (:meth:`EdgeSamples.at`: static held, dynamic interpolated).
        3. ``T_base_frame = T_A_base^-1 T_A_frame``.

        Examples
        --------
        >>> tree = TransformTree.from_transforms([
        ...     (0, "base", "flange", [0, 0, 0.0], [0, 0, 0, 1], False),
        ...     (2_000_000_000, "base", "flange", [0.2, 0, 0.0], [0, 0, 0, 1], False),
        ...     (0, "flange", "camera", [0, 0, 0.05], [0, 0, 0, 1], True)])
        >>> tree.chain_poses("base", "camera", [500_000_000])[0].translation.round(6)
        array([50., 0., 50.])
        """
        down_b, down_f = self.chain(base, frame)
        s = np.asarray(stamps_ns, dtype=np.int64).reshape(-1)
        tb, rb = self._down(down_b, s, tolerance_s)
        tf, rf = self._down(down_f, s, tolerance_s)
        rot = rb.inv() * rf
        xyz = rb.inv().apply(tf - tb)
        mats = np.atleast_3d(rot.as_matrix()).reshape(-1, 3, 3)
        return [SE3(m, p) for m, p in zip(mats, np.atleast_2d(xyz), strict=True)]
