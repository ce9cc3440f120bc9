"""Parameters of the seed-001 biped (Appendix B), packed for the numba kernels.

Every value here is the seed's Appendix B value unless its docstring says otherwise; every
deviation is argued in ``docs/cpg-model.md`` (section numbers in brackets below).

Neuron numbering follows the seed: CPG neurons 1..12 are array indices 0..11 (left hip
flexor/extensor 1/2, left knee 3/4, left ankle 5/6, right leg 7..12), the posture-controller
neurons p1, p2 are indices 12, 13.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np
from numpy.typing import NDArray

N_NEURONS = 14
"""12 CPG neurons + 2 posture-controller neurons."""
N_STATE = 12 + 2 * N_NEURONS
"""x1..x6, their rates, then u (14) and v (14)."""

# Indices into the packed parameter vector (numba kernels read it positionally).
(
    I_M1, I_M2, I_M3, I_M4, I_M5, I_L1, I_L2, I_L3, I_L4,
    I_KG, I_BG, I_KP, I_BP, I_B,
    I_P1, I_P2, I_P3, I_P4, I_P5, I_P6,
    I_PE1, I_PV1, I_PE2, I_PV2, I_PP1, I_PP2, I_ALPHA, I_DELTA, I_XH, I_XK,
    I_G, I_GAMMA, I_T, I_A, I_BB, I_FB, I_HYST, I_HIP_GATE, I_ANKLE_GATE,
    I_BSP_REPLACES, I_BSP_GATE,
) = range(41)  # fmt: skip
N_PARAMS = 41


@dataclass(frozen=True)
class CpgParams:
    """Model constants (SI units). Defaults: Appendix B with the documented resolutions.

    Attributes:
        m1: hip point mass (kg). m2, m4: thighs; m3, m5: shanks.
        l1, l3: thigh lengths (m); l2, l4: shank lengths (m). Link inertias are m l²/12 [§2.3].
        kg, bg: ground spring (N/m) and damper (N s/m), eq. A ground forces.
        kp, bp: knee hyper-extension stop (Nm/rad, Nm s/rad); b: joint viscosity (Nm s/rad).
        p1..p6: active torque gains (Nm per unit neuron output) [§2.6: gain_scale applied].
        pp1, pp2, alpha, delta: the posture controller's torque constants (2.4), scaled by the
            same gain_scale as p1..p6: they are neural torques too [§2.4].
        pe1, pv1: hip-range stop; pe2, pv2: knee-range stop (restoring, [§2.4]).
        pp1, pp2: posture-controller knee stiffness/damping (2.4) [§2.4 sign].
        alpha: antagonist weight of the posture neuron in (2.4) [§2.4]; delta: torque limit f_m.
        xh: hip range (rad); xk: knee range (rad).
        g: gravity (m/s²). gamma: tonic input u0 [§2.6]; T: hip height below which u0 = 0 (2.2).
        a, b_bvp: BVP constants. feedback_gain: scale of the thigh-angle feedback E.
        contact_hysteresis_m: a foot leaves the ground only above this height [§2.5].
        hip_stop_gated: 1 gates the hip-range stop by the hip flexor's firing (a reading of the
            OCR's ``g(u1)``), 0 (default) applies it whenever the range is exceeded [§2.4].
        ankle_swing_flexor: 1 gates only the p6 term of the ankle torque by stance (the literal
            print), 0 (default) gates the whole ankle torque: no foot, no torque in swing [§2.4].
        u1_init: u1(0), the symmetry breaker of the initial condition [§2.8].
        bsp_replaces_cpg: 0 (default) adds T_BSP to the CPG knee torque, as Appendix A prints
            q3, q4; 1 withholds the CPG knee torque while T_BSP acts (the earlier reading) [§2.4].
        bsp_literal_gate: 1 applies the printed gate g(x3 - x4 - φc) (T_BSP only extends,
            flexion from -α f(u_p)); 0 (default) a two-sided PD to φc [§2.4].
        tau, tau_rate: per-neuron time constant τ_i (s) and accommodation rate τ'_i (1/s) [§2.1].
    """

    m1: float = 48.0
    m2: float = 7.0
    m3: float = 4.0
    m4: float = 7.0
    m5: float = 4.0
    l1: float = 0.4
    l2: float = 0.5
    l3: float = 0.4
    l4: float = 0.5
    kg: float = 30000.0
    bg: float = 3000.0
    kp: float = 2000.0
    bp: float = 200.0
    b: float = 1.0
    gain_scale: float = 1.87
    p1: float = 19.0
    p2: float = 19.0
    p3: float = 24.5
    p4: float = 19.0
    p5: float = 18.0
    p6: float = 5.0
    pe1: float = 300.0
    pv1: float = 30.0
    pe2: float = 400.0
    pv2: float = 40.0
    pp1: float = 400.0
    pp2: float = 40.0
    alpha: float = 0.0
    delta: float = 90.0
    xh: float = 0.11 * np.pi
    xk: float = 0.3 * np.pi
    g: float = 9.8
    gamma: float = 1.202
    T: float = 0.1
    a: float = 0.7
    b_bvp: float = 0.8
    feedback_gain: float = 2.058
    contact_hysteresis_m: float = 0.002
    hip_stop_gated: float = 0.0
    ankle_swing_flexor: float = 0.0
    u1_init: float = 0.224
    bsp_replaces_cpg: float = 0.0
    bsp_literal_gate: float = 0.0

    @property
    def body_mass_kg(self) -> float:
        return self.m1 + self.m2 + self.m3 + self.m4 + self.m5

    @property
    def body_weight_n(self) -> float:
        return self.body_mass_kg * self.g

    @property
    def leg_length_m(self) -> float:
        return self.l1 + self.l2

    def replace(self, **changes: float) -> CpgParams:
        """A copy with some fields changed (unknown names raise TypeError)."""
        values = {f.name: getattr(self, f.name) for f in fields(self)}
        values.update(changes)
        return CpgParams(**values)

    def packed(self) -> NDArray[np.float64]:
        """The ``(N_PARAMS,)`` vector the kernels read (neural gains multiplied by gain_scale)."""
        s = self.gain_scale
        return np.array(
            [
                self.m1, self.m2, self.m3, self.m4, self.m5, self.l1, self.l2, self.l3, self.l4,
                self.kg, self.bg, self.kp, self.bp, self.b,
                s * self.p1, s * self.p2, s * self.p3, s * self.p4, s * self.p5, s * self.p6,
                self.pe1, self.pv1, self.pe2, self.pv2, s * self.pp1, s * self.pp2, s * self.alpha,
                s * self.delta, self.xh, self.xk,
                self.g, self.gamma, self.T, self.a, self.b_bvp, self.feedback_gain,
                self.contact_hysteresis_m, self.hip_stop_gated, self.ankle_swing_flexor,
                self.bsp_replaces_cpg, self.bsp_literal_gate,
            ],
            dtype=np.float64,
        )  # fmt: skip


def time_constants() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(tau, tau_rate)``, each ``(14,)``: τ_i in s and τ'_i as a rate in 1/s [§2.1].

    Neurons 4, 10, p1, p2 are the fast ones: τ = 1/50 s, τ' = 20/3 s⁻¹; the rest 1/30 s, 10/3 s⁻¹.
    """
    tau = np.full(N_NEURONS, 1.0 / 30.0)
    rate = np.full(N_NEURONS, 10.0 / 3.0)
    for i in (3, 9, 12, 13):
        tau[i] = 1.0 / 50.0
        rate[i] = 20.0 / 3.0
    return tau, rate


def weights() -> NDArray[np.float64]:
    """``(14, 14)`` connection matrix ``W[source, target]`` (Appendix B, 1-based names) [§2.2]."""
    w = np.zeros((N_NEURONS, N_NEURONS))
    minus_one = [
        (1, 5), (2, 6), (2, 4), (4, 3),
        (7, 11), (8, 12), (8, 10), (10, 9),
        (5, 6), (6, 5), (1, 7), (7, 1),
        (11, 12), (12, 11), (2, 8), (8, 2),
        (4, 13), (10, 14),  # 4 -> p1, 10 -> p2
    ]  # fmt: skip
    for src, dst in minus_one:
        w[src - 1, dst - 1] = -1.0
    for src, dst in [(1, 2), (2, 1), (7, 8), (8, 7)]:
        w[src - 1, dst - 1] = -2.0
    for src, dst in [(1, 3), (2, 3), (7, 9), (8, 9)]:
        w[src - 1, dst - 1] = 1.0
    return w
