"""SMER graph dynamics: scheduling by multiple edge reversal (seed 002, section 2.1).

Nodes ``i`` have a reversibility ``r_i``; the edge between ``i`` and ``j`` carries ``e_ij`` shared
resources, each held at one end. A node *operates* (is a sink) iff it holds at least ``r_i`` of the
resources of every incident edge; operating, it reverses ``r_i`` resources to each neighbour.

Every step here is synchronous: all nodes that can operate do so at once. The seed's coupling
rules are checked when a graph is built, per edge:

1. ``max(r_i, r_j) <= e_ij <= r_i + r_j - 1`` (below: deadlock; above: neighbours can operate in
   the same step, the mutual exclusion SMER exists for is lost);
2. ``f_ij = r_i + r_j - gcd(r_i, r_j)``, with ``f_ij`` the sum of the largest multiples of the gcd
   not exceeding the resources initially held at each end (otherwise the pair deadlocks).

These are pairwise rules; on a graph with cycles an initial orientation can still deadlock (a
cycle of nodes each waiting for the next). :meth:`SmerGraph.step` raises
:class:`~animstudio.errors.SimulationError` the moment no node can operate, and
:func:`check_live` finds that at construction time by running the finite-state dynamics into its
cycle.
"""

from __future__ import annotations

from dataclasses import dataclass
from math import gcd

import numpy as np
from numpy.typing import NDArray

from animstudio.errors import SimulationError

I64 = NDArray[np.int64]


class SmerConfigError(SimulationError, ValueError):
    """A SMER graph breaks the seed's coupling rules (would deadlock or lose mutual exclusion)."""


def pair_f(held_i: int, held_j: int, r_i: int, r_j: int) -> int:
    """The seed's ``f_ij`` of an initial split: gcd-multiples held at each end, summed."""
    g = gcd(r_i, r_j)
    return g * (held_i // g) + g * (held_j // g)


def check_edge(name_i: str, name_j: str, r_i: int, r_j: int, e_ij: int, held_i: int) -> None:
    """Raise :class:`SmerConfigError` naming the edge if it breaks coupling rule 1 or 2."""
    where = f"edge {name_i}-{name_j} (r = {r_i}, {r_j}; e = {e_ij})"
    if not max(r_i, r_j) <= e_ij <= r_i + r_j - 1:
        raise SmerConfigError(
            f"{where}: needs max(r_i, r_j) <= e_ij <= r_i + r_j - 1, "
            f"i.e. {max(r_i, r_j)} <= e <= {r_i + r_j - 1}"
        )
    if not 0 <= held_i <= e_ij:
        raise SmerConfigError(
            f"{where}: {held_i} resources held at {name_i} is outside [0, {e_ij}]"
        )
    f = pair_f(held_i, e_ij - held_i, r_i, r_j)
    want = r_i + r_j - gcd(r_i, r_j)
    if f != want:
        raise SmerConfigError(
            f"{where}: initial split {held_i}/{e_ij - held_i} gives f_ij = {f}, the rule needs "
            f"r_i + r_j - gcd = {want}"
        )


def valid_split(r_i: int, r_j: int, e_ij: int, *, prefer_i: bool) -> int:
    """Resources to hold at ``i`` for a split meeting rule 2, the most at ``i`` (or at ``j``)."""
    order = range(e_ij, -1, -1) if prefer_i else range(e_ij + 1)
    for held_i in order:
        if pair_f(held_i, e_ij - held_i, r_i, r_j) == r_i + r_j - gcd(r_i, r_j):
            return held_i
    raise SmerConfigError(f"no initial split of e = {e_ij} meets rule 2 for r = {r_i}, {r_j}")


@dataclass(frozen=True, eq=False)
class SmerGraph:
    """A SMER system: nodes, reversibilities and edges (the state lives in ``held`` arrays).

    Attributes:
        names: ``(N,)`` node names (for messages and plots).
        r: ``(N,) int64`` reversibility of each node, ``>= 1``.
        edges: ``(E, 2) int64`` node index pairs ``(i, j)``, ``i != j``, no duplicates.
        e: ``(E,) int64`` shared resources per edge.
    """

    names: tuple[str, ...]
    r: I64
    edges: I64
    e: I64

    def __post_init__(self) -> None:
        n = len(self.names)
        r = np.asarray(self.r, dtype=np.int64)
        edges = np.asarray(self.edges, dtype=np.int64).reshape(-1, 2)
        e = np.asarray(self.e, dtype=np.int64)
        if r.shape != (n,) or np.any(r < 1):
            raise SmerConfigError(f"r must be ({n},) integers >= 1, got {r.tolist()}")
        if e.shape != (edges.shape[0],):
            raise SmerConfigError(
                f"e must have one entry per edge ({edges.shape[0]}), got {e.shape}"
            )
        if edges.size and (
            edges.min() < 0 or edges.max() >= n or np.any(edges[:, 0] == edges[:, 1])
        ):
            raise SmerConfigError("edges must join two different existing nodes")
        if len({tuple(sorted(p)) for p in edges.tolist()}) != len(edges):
            raise SmerConfigError("duplicate edge")
        for arr in (r, edges, e):
            arr.setflags(write=False)
        object.__setattr__(self, "r", r)
        object.__setattr__(self, "edges", edges)
        object.__setattr__(self, "e", e)

    @property
    def num_nodes(self) -> int:
        return len(self.names)

    def check(self, held: I64) -> None:
        """Check both coupling rules for the initial state ``held`` (resources at each edge's ``i``)."""
        held = np.asarray(held, dtype=np.int64)
        if held.shape != self.e.shape:
            raise SmerConfigError(f"held must be ({len(self.e)},), got {held.shape}")
        for k, (i, j) in enumerate(self.edges.tolist()):
            check_edge(
                self.names[i],
                self.names[j],
                int(self.r[i]),
                int(self.r[j]),
                int(self.e[k]),
                int(held[k]),
            )

    def ready(self, held: I64) -> NDArray[np.bool_]:
        """``(N,)`` which nodes hold ``r_i`` resources of every incident edge (can operate now)."""
        i, j = self.edges[:, 0], self.edges[:, 1]
        ok = np.ones(self.num_nodes, dtype=bool)
        # A node with a short edge end is not ready; np.logical_and.at folds every incident edge.
        np.logical_and.at(ok, i, held >= self.r[i])
        np.logical_and.at(ok, j, (self.e - held) >= self.r[j])
        return ok

    def step(self, held: I64) -> tuple[I64, NDArray[np.bool_]]:
        """One synchronous step: every ready node operates. Returns ``(new held, fired (N,))``.

        Raises:
            SimulationError: no node can operate (deadlock).
        """
        fired = self.ready(held)
        if not fired.any():
            raise SimulationError(
                "SMER deadlock: no node can operate (holdings "
                + ", ".join(
                    f"{self.names[a]}-{self.names[b]}: {h}/{ek - h}"
                    for (a, b), h, ek in zip(
                        self.edges.tolist(), held.tolist(), self.e.tolist(), strict=True
                    )
                )
                + ")"
            )
        i, j = self.edges[:, 0], self.edges[:, 1]
        new = held - np.where(fired[i], self.r[i], 0) + np.where(fired[j], self.r[j], 0)
        return new, fired

    def run(self, held: I64, steps: int) -> tuple[I64, NDArray[np.bool_]]:
        """``steps`` synchronous steps from ``held``: final holdings and ``(steps, N)`` firings."""
        out = np.zeros((steps, self.num_nodes), dtype=bool)
        cur = np.asarray(held, dtype=np.int64)
        for t in range(steps):
            cur, out[t] = self.step(cur)
        return cur, out


def find_cycle(graph: SmerGraph, held: I64, *, max_steps: int = 100_000) -> tuple[int, int]:
    """Run until a state repeats: ``(transient steps, period)``. Raises on deadlock.

    The state space is finite and the dynamics deterministic, so every run ends in a cycle.
    """
    seen: dict[bytes, int] = {}
    cur = np.asarray(held, dtype=np.int64)
    for t in range(max_steps):
        key = cur.tobytes()
        if key in seen:
            return seen[key], t - seen[key]
        seen[key] = t
        cur, _ = graph.step(cur)
    raise SimulationError(f"SMER graph did not repeat a state within {max_steps} steps")


def check_live(graph: SmerGraph, held: I64) -> tuple[int, int]:
    """Check the rules and run into the cycle: raises on a bad configuration or a deadlock.

    Returns:
        ``(transient steps, period)`` of the run from ``held``.
    """
    graph.check(held)
    return find_cycle(graph, held)
