"""Fast checks of the biped's equations and kernels (no walking needed)."""

from __future__ import annotations

import numpy as np
import pytest

from animstudio.errors import SimulationError
from animstudio.sim.cpg import integrator as ig
from animstudio.sim.cpg.dynamics import N_AUX, N_WORK, rhs
from animstudio.sim.cpg.model import Drive, Model, Push, init, rollout, step
from animstudio.sim.cpg.params import N_STATE, CpgParams, time_constants, weights


def _energy(p: CpgParams, y: np.ndarray) -> float:
    """Kinetic + potential energy of the 5 links computed from link kinematics (reference)."""
    _, x2, x3, x4, x5, x6 = y[:6]
    d = y[6:12]
    total = 0.5 * p.m1 * (d[0] ** 2 + d[1] ** 2) + p.m1 * p.g * x2
    for th, sh, dth, dsh, l_th, l_sh, m_th, m_sh in (
        (x3, x4, d[2], d[3], p.l1, p.l2, p.m2, p.m3),
        (x5, x6, d[4], d[5], p.l3, p.l4, p.m4, p.m5),
    ):
        # thigh centre of mass
        vx = d[0] + 0.5 * l_th * np.cos(th) * dth
        vy = d[1] + 0.5 * l_th * np.sin(th) * dth
        yc = x2 - 0.5 * l_th * np.cos(th)
        total += 0.5 * m_th * (vx**2 + vy**2) + m_th * l_th**2 / 24 * dth**2 + m_th * p.g * yc
        # shank centre of mass
        vx = d[0] + l_th * np.cos(th) * dth + 0.5 * l_sh * np.cos(sh) * dsh
        vy = d[1] + l_th * np.sin(th) * dth + 0.5 * l_sh * np.sin(sh) * dsh
        yc = x2 - l_th * np.cos(th) - 0.5 * l_sh * np.cos(sh)
        total += 0.5 * m_sh * (vx**2 + vy**2) + m_sh * l_sh**2 / 24 * dsh**2 + m_sh * p.g * yc
    return float(total)


def test_body_equations_conserve_energy_in_flight() -> None:
    # No muscles, no viscosity, no stops, high in the air: P(x) and Q must be one Lagrangian.
    p = CpgParams().replace(
        gain_scale=0.0, b=0.0, kp=0.0, bp=0.0, pe1=0.0, pv1=0.0, pe2=0.0, pv2=0.0
    )
    model = Model.build(p)
    state = init(p)
    y = state.y.copy()
    y[1] = 50.0
    y[2:6] = [0.4, -0.3, -0.2, 0.5]
    y[6:12] = [1.0, 2.0, 3.0, -4.0, 2.5, 1.5]
    ro = rollout(model, type(state)(0.0, y, state.disc.copy()), 1.0, dt=2.5e-4, record_every=100)
    energies = [_energy(p, np.concatenate([r[ig.C_X : ig.C_X + 12]])) for r in ro.records]
    assert np.ptp(energies) < 1e-6 * abs(energies[0]) + 1e-6
    # and it did move: the links swung through large angles
    assert np.ptp(ro.records[:, ig.C_X + 3]) > 1.0


def test_step_matches_rollout() -> None:
    # the per-step Python path and the compiled rollout loop agree bit for bit
    p = CpgParams()
    model = Model.build(p)
    s = init(p)
    for _ in range(200):
        s = step(model, s, 5e-4, Drive())
    ro = rollout(model, init(p), 200 * 5e-4, record_every=1 << 20)
    np.testing.assert_array_equal(s.y, ro.final.y)
    np.testing.assert_array_equal(s.disc, ro.final.disc)


def test_weights_mirror_left_right() -> None:
    w = weights()
    mirror = np.r_[6:12, 0:6, 13, 12]
    np.testing.assert_array_equal(w, w[np.ix_(mirror, mirror)])
    assert w[0, 1] == w[1, 0] == -2.0  # hip flexor/extensor pair
    assert w[3, 12] == -1.0  # neuron 4 -> p1 entrains the posture controller
    tau, rate = time_constants()
    assert tau[3] == tau[12] == 1 / 50 and rate[3] == 20 / 3 and rate[0] == 10 / 3


def test_symmetric_start_does_not_walk() -> None:
    # the seed's initial condition is exactly symmetric: without u1(0) both legs move alike
    p = CpgParams().replace(u1_init=0.0)
    ro = rollout(Model.build(p), init(p), 2.0, record_every=10)
    early = ro.records[:, ig.C_T] < 0.5
    np.testing.assert_allclose(
        ro.records[early, ig.C_X + 2], ro.records[early, ig.C_X + 4], atol=1e-12
    )
    assert np.ptp(ro.records[early, ig.C_X + 2]) > 0.01  # the legs did move, together
    assert ro.fall_t_s is not None


def test_ground_holds_a_standing_body() -> None:
    # muscles off: the straight body sinks into the ground springs by about weight / (2 kg)
    p = CpgParams().replace(gamma=0.0, u1_init=0.0)
    ro = rollout(Model.build(p), init(p), 1.0, record_every=100)
    sink = p.l1 + p.l2 - ro.final.y[1]
    assert sink == pytest.approx(p.body_weight_n / (2 * p.kg), rel=0.05)
    assert ro.final.disc[0] == 1.0 and ro.final.disc[2] == 1.0


def test_push_is_applied_for_its_duration() -> None:
    p = CpgParams().replace(gamma=0.0, u1_init=0.0, kg=0.0, bg=0.0)  # free fall, no ground
    ro = rollout(Model.build(p), init(p), 0.3, record_every=1, pushes=[Push(0.1, 70.0, 0.1)])
    push = ro.records[:, ig.C_PUSH]
    t = ro.records[:, ig.C_T]
    assert np.all(push[(t >= 0.1 + 1e-9) & (t < 0.2 - 1e-9)] == 70.0)
    assert np.all(push[(t < 0.1 - 1e-9) | (t > 0.2 + 1e-9)] == 0.0)
    # impulse 7 N s on the whole body: its centre of mass gains 7 / 70 = 0.1 m/s forward
    y = ro.final.y
    momentum = p.body_mass_kg * y[6] + sum(
        c * np.cos(y[i]) * y[6 + i]
        for i, c in (
            (2, (0.5 * p.m2 + p.m3) * p.l1),
            (3, 0.5 * p.m3 * p.l2),
            (4, (0.5 * p.m4 + p.m5) * p.l3),
            (5, 0.5 * p.m5 * p.l4),
        )
    )
    assert momentum / p.body_mass_kg == pytest.approx(7.0 / p.body_mass_kg, rel=1e-6)


def test_rhs_reports_torques_and_is_finite() -> None:
    p = CpgParams()
    model = Model.build(p)
    y = init(p).y.copy()
    y[12:26] = 1.5
    dy = np.zeros(N_STATE)
    aux = np.zeros(N_AUX)
    rhs(
        model.packed,
        model.tau,
        model.rate,
        model.w,
        y,
        np.zeros(4),
        0.0,
        0.0,
        0.0,
        1.0,
        dy,
        aux,
        np.zeros(N_WORK),
    )
    assert np.all(np.isfinite(dy))
    assert aux[0] == pytest.approx((p.p1 - p.p2) * p.gain_scale * 1.5)


def _knee_torques(p: CpgParams, phi_c: float) -> np.ndarray:
    """aux of a walker with its left foot 5 cm up, left knee flexed 0.3π, p1 firing."""
    model = Model.build(p)
    y = init(p).y.copy()
    y[1] += 0.05
    y[2], y[3] = 0.2 * np.pi, -0.1 * np.pi  # knee angle x3 - x4 = 0.3π
    y[12:26] = -1.0
    y[12 + 2] = 1.5  # neuron 3 (knee extensor) and p1 fire
    y[12 + 12] = 1.5
    dy = np.zeros(N_STATE)
    aux = np.zeros(N_AUX)
    args = (model.packed, model.tau, model.rate, model.w, y, np.zeros(4), 0.0, phi_c, 0.0, 1.0)
    rhs(*args, dy, aux, np.zeros(N_WORK))
    return aux


def test_posture_torque_is_added_to_the_cpg_knee_torque() -> None:
    # Appendix A: q3 has -Tr2 - T_BSPl, q4 has +Tr2 + T_BSPl; both act at once (docs §2.4)
    p = CpgParams()
    free = _knee_torques(p, 0.0)
    aux = _knee_torques(p, 0.1 * np.pi)
    assert free[6] == 0.0  # φc = 0: no posture modulation at all
    assert aux[1] == pytest.approx(p.p3 * p.gain_scale * 1.5)  # the CPG knee torque stays
    # the knee is 0.2π past φc: the PD saturates at +δ (extension), δ scaled like the gains
    assert aux[6] == pytest.approx(p.delta * p.gain_scale)
    # the old reading withheld the CPG knee torque in that window
    replaced = _knee_torques(p.replace(bsp_replaces_cpg=1.0), 0.1 * np.pi)
    assert replaced[1] == 0.0 and replaced[6] == aux[6]
    # the printed one-sided gate: below φc no PD, only the antagonist -α f(u_p)
    lit = p.replace(bsp_literal_gate=1.0, alpha=50.0)
    below = _knee_torques(lit, 0.35 * np.pi)
    assert below[6] == pytest.approx(-50.0 * p.gain_scale * 1.5)


def test_blow_up_is_a_simulation_error() -> None:
    p = CpgParams()
    with pytest.raises(SimulationError, match="non-finite"):
        rollout(Model.build(p), init(p), 2.0, dt=1e-2, fall_height_m=-np.inf, knee_floor_m=-np.inf)
