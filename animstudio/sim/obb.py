"""The OBB neuron pair: SMER written as difference equations (seed 002, section 2.2).

Two coupled neurons with reversibilities ``r = (r_flexor, r_extensor)`` (Table 1 order). With
``M`` the membrane potentials and ``v`` the outputs, equation (1) is::

    M(t) = M(t-1) + W v(t-1),   W = (1 / r') [[-r_f,  r_e],
                                              [ r_f, -r_e]]

and (2) ``v_k(t) = max(0, sgn(M_k(t) - θ_k))``: a neuron is on iff its potential is *strictly*
above its threshold (firing on ``>=`` lets both neurons fire together in Table 1's case).
``r' = h(max r)`` is 10 to the number of digits of the larger reversibility (``h(5) = 10``,
``h(463) = 1000``); thresholds ``θ_e = r_e / f`` and ``θ_f = 1 - θ_e`` with
``f = r_f + r_e - gcd(r_f, r_e)`` (this is what Tables 1 and 2 list: 0 and 1 for every phase;
the text's ``θ_j^new = (r_j + r_j^d) / f^new`` contradicts both tables and ``θ_j = 1 - θ_i``).

A transition (equations (3)-(4)) replaces ``W`` and the thresholds by those of the new
reversibilities from the step it is requested. Because a weight column only acts while its
neuron is on, the new reversibility of a neuron takes effect at its next firing: the
self-organisation delay the seed describes. The transition section divides the new weights by
``r``; read as ``r'`` (equation (3) and Table 2's weights 0.3 and 0.1 agree with that).

The arithmetic is exact (:class:`fractions.Fraction`): potentials land exactly on thresholds
(e.g. 0.5 + 5 x 0.1 = 1.0), where float rounding would decide the firing.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from math import gcd

import numpy as np
from numpy.typing import NDArray

from animstudio.errors import SimulationError

MAX_REVERSIBILITY = 999
"""Largest reversibility accepted (``h`` stays a small power of ten)."""


def h(r: int) -> int:
    """The seed's ``h``: 10 to the number of decimal digits of ``r`` (``h(5) = 10``)."""
    return 10 ** len(str(int(r)))


@dataclass(frozen=True)
class ObbParams:
    """Weights and thresholds of an OBB pair derived from its reversibilities.

    Attributes:
        r_flexor: reversibility of the flexor (Table 1 column 1; 1 in every table).
        r_extensor: reversibility of the extensor (5, 3, 1 in Table 2's phases).
    """

    r_flexor: int
    r_extensor: int

    def __post_init__(self) -> None:
        for name, r in (("r_flexor", self.r_flexor), ("r_extensor", self.r_extensor)):
            if not isinstance(r, int) or not 1 <= r <= MAX_REVERSIBILITY:
                raise SimulationError(
                    f"{name} must be an integer in [1, {MAX_REVERSIBILITY}], got {r!r}"
                )

    @property
    def r_prime(self) -> int:
        return h(max(self.r_flexor, self.r_extensor))

    @property
    def f(self) -> int:
        return self.r_flexor + self.r_extensor - gcd(self.r_flexor, self.r_extensor)

    @property
    def thresholds(self) -> tuple[Fraction, Fraction]:
        """``(θ_flexor, θ_extensor)``."""
        theta_e = Fraction(self.r_extensor, self.f)
        return 1 - theta_e, theta_e

    @property
    def weights(self) -> tuple[Fraction, Fraction]:
        """``(w_flexor, w_extensor) = r / r'``: what each neuron passes on when it fires (Table 1)."""
        return Fraction(self.r_flexor, self.r_prime), Fraction(self.r_extensor, self.r_prime)


@dataclass(frozen=True, eq=False)
class PairRun:
    """A simulated OBB pair, index 0 the flexor and 1 the extensor.

    Attributes:
        m: ``(T, 2) float64`` membrane potentials at steps ``0 .. T-1``.
        v: ``(T, 2) bool`` outputs.
        r: ``(T, 2) int64`` reversibilities in force at each step.
    """

    m: NDArray[np.float64]
    v: NDArray[np.bool_]
    r: NDArray[np.int64]

    @property
    def num_steps(self) -> int:
        return int(self.v.shape[0])


def simulate_pair(
    steps: int,
    *,
    r: tuple[int, int] = (1, 5),
    m0: tuple[float | str, float | str] = ("0.35", "0.65"),
    switches: Sequence[tuple[int, tuple[int, int]]] = (),
) -> PairRun:
    """Run equations (1)-(4) for ``steps`` steps.

    Args:
        steps: number of steps (step 0 is the initial state).
        r: ``(r_flexor, r_extensor)`` at step 0.
        m0: initial potentials ``(flexor, extensor)``; strings are read exactly (``"0.35"``).
        switches: ``(step, (r_flexor, r_extensor))`` transitions: from ``step`` on, ``M`` is
            updated with the new weights and compared with the new thresholds (eq. (3)-(4)).

    Raises:
        SimulationError: bad reversibilities, unordered switches, or a pair that stops
            oscillating (neither neuron on: the potentials can no longer change).
    """
    if steps < 1:
        raise SimulationError(f"steps must be >= 1, got {steps}")
    plan = sorted(switches)
    if [s for s, _ in plan] != [s for s, _ in switches] or any(s < 1 for s, _ in plan):
        raise SimulationError("switch steps must be increasing and >= 1")
    params = ObbParams(*r)
    pending = [(s, ObbParams(*rr)) for s, rr in plan]
    m = [Fraction(str(x)) if isinstance(x, float) else Fraction(x) for x in m0]
    out_m = np.empty((steps, 2))
    out_v = np.zeros((steps, 2), dtype=bool)
    out_r = np.empty((steps, 2), dtype=np.int64)
    theta = params.thresholds
    v = (m[0] > theta[0], m[1] > theta[1])
    for t in range(steps):
        if t > 0:
            while pending and pending[0][0] == t:
                params = pending.pop(0)[1]
                theta = params.thresholds
            w_f, w_e = params.weights
            # eq. (1)/(3): the firing neuron hands its weight to the other one.
            delta = w_e * v[1] - w_f * v[0]
            m = [m[0] + delta, m[1] - delta]
            v = (m[0] > theta[0], m[1] > theta[1])
        out_m[t] = [float(m[0]), float(m[1])]
        out_v[t] = v
        out_r[t] = [params.r_flexor, params.r_extensor]
        if not (v[0] or v[1]):
            raise SimulationError(
                f"OBB pair r = {params.r_flexor},{params.r_extensor} stopped at step {t}: "
                f"potentials {float(m[0]):.3f}, {float(m[1]):.3f} are below both thresholds"
            )
    return PairRun(m=out_m, v=out_v, r=out_r)


@dataclass(frozen=True)
class Cycle:
    """A periodic stretch of one neuron's output, in steps.

    Attributes:
        start: step at which the neuron switched on (start of the cycle).
        period: steps from this switch-on to the next.
        on: steps the neuron stayed on within the cycle.
    """

    start: int
    period: int
    on: int

    @property
    def duty(self) -> float:
        return self.on / self.period


def cycles(v: NDArray[np.bool_]) -> list[Cycle]:
    """Every complete on/off cycle of a boolean output ``(T,)`` (switch-on to switch-on)."""
    v = np.asarray(v, dtype=bool)
    rises = np.flatnonzero(v[1:] & ~v[:-1]) + 1
    return [
        Cycle(
            start=int(a),
            period=int(b - a),
            on=int(np.argmin(v[a:b])) if not v[a:b].all() else int(b - a),
        )
        for a, b in itertools.pairwise(rises)
    ]


def settle_step(
    v: NDArray[np.bool_], *, period: int, on: int, after: int = 0, before: int | None = None
) -> int | None:
    """First switch-on in ``[after, before)`` from which every later cycle there is ``(period, on)``."""
    end = len(v) if before is None else before
    cs = [c for c in cycles(v) if after <= c.start < end]
    first = None
    for c in cs:
        if (c.period, c.on) == (period, on):
            first = c.start if first is None else first
        else:
            first = None
    return first
