"""The hexapod OBB network: six one-joint legs coupled as SMER nodes (seed 002, Figure 2).

Each leg is an OBB pair (:mod:`animstudio.sim.obb`): a *stance* node with reversibility 1 and a
*swing* node with reversibility ``k``, sharing ``e = k`` resources. In a pair the reversibility-1
neuron is on ``k`` steps out of ``k + 1`` (Figure 3: on 15 s of 18 s), so it is the one that
holds the foot on the ground; which neuron is stance is decided by reversibility, not by the
paper's flexor/extensor labels (Table 1 gives r = 1 to the flexor, the text calls the long burst
the extensor's; docs/obb-model.md).

Legs are coupled through their swing nodes in a ring of six SMER edges with reversibility ``k``
at both ends and ``e = k`` resources, i.e. plain edge reversal: neighbouring legs never swing in
the same step. The ring's *tokens* (edges oriented along the ring) are invariant under the
dynamics and fix the gait class; ``k`` only sets the refractory stance time:

======== ========================= ====== === ======== ===========
gait     ring                      tokens k   period   duty factor
======== ========================= ====== === ======== ===========
wave     L3 L2 L1 R3 R2 R1         1      5   6 steps  5/6
tetrapod L3 L2 L1 R2 R1 R3         2      2   3 steps  2/3
tripod   L3 L2 L1 R3 R2 R1         3      1   2 steps  1/2
======== ========================= ====== === ======== ===========

Changing ``k`` (the paper's transition, eq. (3)-(4)) acts at each leg's next swing. Changing the
class needs the ring re-oriented: :func:`simulate` re-initialises the network at the requested
step, choosing the phase of the new pattern that keeps every leg's stance closest to a normal one.

The state is kept as ring orientations + stance holdings, which is the SMER graph of
:func:`smer_graph` written out for this topology (tests check both give the same firings).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from animstudio.errors import SimulationError
from animstudio.sim.smer import SmerGraph

LEGS: tuple[str, ...] = ("L1", "L2", "L3", "R1", "R2", "R3")
"""Leg order of every ``(…, 6)`` array here (docs/conventions.md)."""

WAVE_RING: tuple[str, ...] = ("L3", "L2", "L1", "R3", "R2", "R1")
TETRAPOD_RING: tuple[str, ...] = ("L3", "L2", "L1", "R2", "R1", "R3")
MAX_K = 9
"""Largest swing reversibility of the expert ``obb r=1,k`` form (keeps the paper's r' = 10)."""


@dataclass(frozen=True)
class Gait:
    """A gait of the network.

    Attributes:
        name: script name (``wave``, ``tetrapod``, ``tripod`` or ``obb``).
        ring: the six legs in ring order.
        tokens: edges oriented along the ring in the initial orientation (1, 2 or 3).
        k: swing-node reversibility (the stance node's is 1).
    """

    name: str
    ring: tuple[str, ...]
    tokens: int
    k: int

    def __post_init__(self) -> None:
        if sorted(self.ring) != sorted(LEGS):
            raise SimulationError(
                f"gait {self.name!r}: ring must list each leg once, got {self.ring}"
            )
        if self.tokens not in (1, 2, 3):
            raise SimulationError(
                f"gait {self.name!r}: tokens must be 1, 2 or 3, got {self.tokens}"
            )
        if not 1 <= self.k <= MAX_K:
            raise SimulationError(f"gait {self.name!r}: k must be in [1, {MAX_K}], got {self.k}")

    @property
    def ring_period(self) -> int:
        """Steps between two swings of a leg allowed by the ring alone."""
        return len(LEGS) // self.tokens

    @property
    def period(self) -> int:
        """Steady-state steps per leg cycle: the ring's period or the pair's ``k + 1``, the longer."""
        return max(self.ring_period, self.k + 1)

    def same_class(self, other: Gait) -> bool:
        return self.ring == other.ring and self.tokens == other.tokens


GAITS: dict[str, Gait] = {
    "wave": Gait("wave", WAVE_RING, 1, 5),
    "tetrapod": Gait("tetrapod", TETRAPOD_RING, 2, 2),
    "tripod": Gait("tripod", WAVE_RING, 3, 1),
}


def obb_gait(k: int, *, like: Gait | None) -> Gait:
    """The expert ``obb r=1,k`` gait: reversibility ``k`` in the class of ``like`` (wave if none)."""
    base = like or GAITS["wave"]
    return Gait("obb", base.ring, base.tokens, k)


@dataclass(frozen=True, eq=False)
class NetworkRun:
    """Firings of the hexapod network, one row per step, columns in :data:`LEGS` order.

    Attributes:
        swing: ``(S, 6) bool`` swing node operated (the leg is in the air during the step).
        stance: ``(S, 6) bool`` stance node operated.
        k: ``(S, 6) int64`` swing reversibility in force at each step.
        reinit_steps: steps at which the ring was re-initialised (gait class changes).
    """

    swing: NDArray[np.bool_]
    stance: NDArray[np.bool_]
    k: NDArray[np.int64]
    reinit_steps: tuple[int, ...]

    @property
    def num_steps(self) -> int:
        return int(self.swing.shape[0])


def _orientation(tokens: int, offset: int) -> NDArray[np.bool_]:
    """Ring edge ``m`` (ring[m]–ring[m+1]) points at ring[m+1]: the sinks are ``offset + j·6/T``."""
    toward_next = np.zeros(len(LEGS), dtype=bool)
    for j in range(tokens):
        sink = (offset + j * len(LEGS) // tokens) % len(LEGS)
        toward_next[(sink - 1) % len(LEGS)] = True
    return toward_next


def _first_swing(gait: Gait, offset: int) -> NDArray[np.int64]:
    """``(6,)`` steps until each leg's first swing when the ring's sinks start at ``offset``."""
    return np.array([(gait.ring.index(leg) - offset) % gait.ring_period for leg in LEGS])


def _initial_stance(gait: Gait, offset: int) -> NDArray[np.int64]:
    """Stance holdings that make a fresh pattern steady from its first step.

    A leg whose first swing is ``w`` steps away starts with ``min(w, k)`` resources at its stance
    node, so its stance neuron is on until then instead of idling (the pair is then already in
    its stable cycle rather than self-organising into it).
    """
    return np.minimum(_first_swing(gait, offset), gait.k)


def _choose_offset(gait: Gait, since_swing: NDArray[np.int64]) -> int:
    """Phase of a re-initialised pattern: no leg swings again too soon, none waits too long.

    ``since_swing`` is ``(6,)`` steps since each leg (LEGS order) last swung. The first swing of
    ring position ``m`` with sinks at ``offset`` is ``(m - offset) mod ring_period`` steps on.
    """
    best: tuple[int, int, int] | None = None
    for offset in range(gait.ring_period):
        gaps = (since_swing + _first_swing(gait, offset)).tolist()
        # Longest shortest stance first, then shortest longest stance, then the lowest offset.
        key = (-min(gaps), max(gaps), offset)
        best = key if best is None or key < best else best
    assert best is not None
    return best[2]


def simulate(schedule: Sequence[tuple[int, Gait]], steps: int) -> NetworkRun:
    """Run the network for ``steps`` steps through a schedule of gaits.

    Args:
        schedule: ``(start step, gait)`` in increasing step order, the first at step 0. A gait of
            the same class as the running one changes ``k`` only (each leg adopts it at its next
            swing, eq. (3)-(4)); another class re-initialises the ring at its start step.
        steps: number of steps.

    Raises:
        SimulationError: an empty or unordered schedule, or a deadlock.
    """
    if not schedule or schedule[0][0] != 0:
        raise SimulationError("the gait schedule must start at step 0")
    starts = [s for s, _ in schedule]
    if starts != sorted(starts):
        raise SimulationError(f"gait schedule steps must increase, got {starts}")
    n = len(LEGS)
    swing = np.zeros((steps, n), dtype=bool)
    stance = np.zeros((steps, n), dtype=bool)
    k_out = np.zeros((steps, n), dtype=np.int64)
    reinit: list[int] = []
    gait = schedule[0][1]
    toward_next = _orientation(gait.tokens, 0)
    held_stance = _initial_stance(gait, 0)  # stance node's share of the pair edge (e = k)
    k = np.full(n, gait.k, dtype=np.int64)
    k_next = k.copy()
    since_swing = np.full(n, gait.period - 1, dtype=np.int64)
    plan = list(schedule[1:])
    for t in range(steps):
        while plan and plan[0][0] <= t:
            new = plan.pop(0)[1]
            if new.same_class(gait):
                k_next[:] = new.k
            else:
                offset = _choose_offset(new, since_swing)
                toward_next = _orientation(new.tokens, offset)
                held_stance = _initial_stance(new, offset)  # re-initialisation of the pairs
                k[:] = new.k
                k_next[:] = new.k
                reinit.append(t)
            gait = new
        pos = np.array([gait.ring.index(leg) for leg in LEGS])
        # Swing node ready: both ring edges point at it and it holds all k pair resources.
        ring_in = toward_next[(pos - 1) % n] & ~toward_next[pos]
        fire_swing = ring_in & (held_stance == 0)
        fire_stance = held_stance >= 1
        if not (fire_swing.any() or fire_stance.any()):
            raise SimulationError(f"hexapod network deadlocked at step {t}")
        # Operating, a swing node reverses its ring edges and hands k (the new k, eq. (3)) over.
        flip = np.zeros(n, dtype=bool)
        flip[pos[fire_swing]] ^= True
        flip[(pos[fire_swing] - 1) % n] ^= True
        toward_next ^= flip
        k = np.where(fire_swing, k_next, k)
        held_stance = held_stance - fire_stance + np.where(fire_swing, k, 0)
        swing[t], stance[t], k_out[t] = fire_swing, fire_stance, k
        since_swing = np.where(fire_swing, 0, since_swing + 1)
    return NetworkRun(swing=swing, stance=stance, k=k_out, reinit_steps=tuple(reinit))


def smer_graph(gait: Gait) -> tuple[SmerGraph, NDArray[np.int64]]:
    """The same network as a plain :class:`SmerGraph` and its initial holdings (reference path).

    Nodes are ``<leg>_stance`` (r = 1) then ``<leg>_swing`` (r = k), in :data:`LEGS` order.
    """
    n = len(LEGS)
    names = tuple(f"{leg}_stance" for leg in LEGS) + tuple(f"{leg}_swing" for leg in LEGS)
    r = np.array([1] * n + [gait.k] * n)
    edges: list[tuple[int, int]] = [(a, n + a) for a in range(n)]
    held: list[int] = _initial_stance(gait, 0).tolist()
    toward_next = _orientation(gait.tokens, 0)
    for m in range(n):
        a, b = LEGS.index(gait.ring[m]), LEGS.index(gait.ring[(m + 1) % n])
        edges.append((n + a, n + b))
        held.append(0 if toward_next[m] else gait.k)  # held at edge end a (= ring[m])
    graph = SmerGraph(names, r, np.array(edges), np.full(len(edges), gait.k))
    held_arr = np.array(held, dtype=np.int64)
    graph.check(held_arr)
    return graph, held_arr


def leg_cycles(swing: NDArray[np.bool_]) -> list[list[tuple[int, int]]]:
    """Per leg, ``(swing step, steps to the next swing)`` for every complete cycle."""
    out = []
    for col in np.asarray(swing, dtype=bool).T:
        on = np.flatnonzero(col)
        out.append([(int(a), int(b - a)) for a, b in itertools.pairwise(on)])
    return out
