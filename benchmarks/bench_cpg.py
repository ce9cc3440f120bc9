"""Speed of the cpg biped: real-time factor, batch throughput, and a MuJoCo reference.

Run: ``PYTHONPATH=. python benchmarks/bench_cpg.py``. Prints one table; every row is measured in
this process. The MuJoCo reference is an equivalent planar 5-link body built here in MJCF (hip
point mass on x/z slides, thighs and shanks on hinges, sphere feet on a ground plane) stepped
with MuJoCo's own RK4 at the same time step; ratio = our cost per step / MuJoCo's (target <= 3).
"""

from __future__ import annotations

import time

import mujoco
import numpy as np
from mujoco import rollout as mj_rollout

from animstudio.sim.cpg.analysis import start_on_cycle
from animstudio.sim.cpg.batch import run_walkers
from animstudio.sim.cpg.model import DT_S, Model, rollout
from animstudio.sim.cpg.params import CpgParams

SIM_S = 60.0
REPEATS = 3


def _mjcf(p: CpgParams, dt: float) -> str:
    def leg(side: str, m_th: float, m_sh: float, l_th: float, l_sh: float) -> str:
        return f"""
        <body name="{side}_thigh">
          <joint name="{side}_hip" type="hinge" axis="0 1 0" damping="1"/>
          <geom type="capsule" fromto="0 0 0 0 0 -{l_th}" size="0.04" mass="{m_th}" contype="0" conaffinity="0"/>
          <body name="{side}_shank" pos="0 0 -{l_th}">
            <joint name="{side}_knee" type="hinge" axis="0 1 0" damping="1" range="-150 0" limited="true"/>
            <geom type="capsule" fromto="0 0 0 0 0 -{l_sh}" size="0.035" mass="{m_sh}" contype="0" conaffinity="0"/>
            <geom name="{side}_foot" type="sphere" pos="0 0 -{l_sh}" size="0.02" mass="0.001"/>
          </body>
        </body>"""

    return f"""
<mujoco model="planar biped">
  <option timestep="{dt}" integrator="RK4" gravity="0 0 -{p.g}"/>
  <worldbody>
    <geom type="plane" size="50 1 0.1"/>
    <body name="hip" pos="0 0 {p.l1 + p.l2 + 0.02}">
      <joint name="x" type="slide" axis="1 0 0"/>
      <joint name="z" type="slide" axis="0 0 1"/>
      <geom type="sphere" size="0.05" mass="{p.m1}" contype="0" conaffinity="0"/>
      {leg("left", p.m2, p.m3, p.l1, p.l2)}
      {leg("right", p.m4, p.m5, p.l3, p.l4)}
    </body>
  </worldbody>
  <actuator>
    <motor joint="left_hip"/><motor joint="left_knee"/><motor joint="right_hip"/><motor joint="right_knee"/>
  </actuator>
</mujoco>"""


def _best(fn, repeats: int = REPEATS) -> float:  # type: ignore[no-untyped-def]
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    params = CpgParams()
    model = Model.build(params)
    start = start_on_cycle(params)  # also compiles the kernels
    steps = round(SIM_S / DT_S)

    ours = _best(lambda: rollout(model, start, SIM_S, record_every=1 << 20))
    ours_rec = _best(lambda: rollout(model, start, SIM_S, record_every=20))

    run_walkers(model, [start] * 4, 0.5)  # compile the parallel kernel
    batch = 64
    batch_s = 5.0
    t_batch = _best(lambda: run_walkers(model, [start] * batch, batch_s))

    mj_model = mujoco.MjModel.from_xml_string(_mjcf(params, DT_S))
    mj_data = mujoco.MjData(mj_model)
    rng = np.random.default_rng(0)

    def mujoco_run() -> None:
        mujoco.mj_resetData(mj_model, mj_data)
        mj_data.qpos[2:] = [0.2, -0.1, -0.2, -0.3]
        for k in range(steps):
            if k % 200 == 0:  # slowly varying joint torques keep the legs moving
                mj_data.ctrl[:] = rng.uniform(-20.0, 20.0, 4)
            mujoco.mj_step(mj_model, mj_data)

    t_mj_py = _best(mujoco_run, repeats=1)

    # the same in MuJoCo's native rollout loop (no Python per step): the fair per-step cost
    mujoco.mj_resetData(mj_model, mj_data)
    mj_data.qpos[2:] = [0.2, -0.1, -0.2, -0.3]
    state0 = np.empty(mujoco.mj_stateSize(mj_model, mujoco.mjtState.mjSTATE_FULLPHYSICS))
    mujoco.mj_getState(mj_model, mj_data, state0, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    control = np.repeat(rng.uniform(-20.0, 20.0, (steps // 200 + 1, 4)), 200, axis=0)[None, :steps]
    t_mj = _best(lambda: mj_rollout.rollout(mj_model, mj_data, state0[None], control))
    mj_euler = mujoco.MjModel.from_xml_string(
        _mjcf(params, DT_S).replace('integrator="RK4"', 'integrator="Euler"')
    )
    t_mj_euler = _best(
        lambda: mj_rollout.rollout(mj_euler, mujoco.MjData(mj_euler), state0[None], control)
    )

    rows = [
        ("ours: one walker, no records", ours, steps),
        ("ours: one walker, record 100 Hz", ours_rec, steps),
        (f"ours: batch of {batch} x {batch_s:g} s", t_batch, round(batch * batch_s / DT_S)),
        ("MuJoCo planar 5-link, RK4, native rollout", t_mj, steps),
        ("MuJoCo same, mj_step from a Python loop", t_mj_py, steps),
        ("MuJoCo same, semi-implicit Euler, native", t_mj_euler, steps),
    ]
    print(f"dt = {DT_S * 1e3:g} ms, {SIM_S:g} simulated s per single run, best of {REPEATS}")
    print(f"{'what':40s} {'wall s':>8s} {'us/step':>9s} {'sim s / wall s':>15s}")
    for name, wall, n in rows:
        print(f"{name:40s} {wall:8.3f} {wall / n * 1e6:9.2f} {n * DT_S / wall:15.1f}")
    per_ours = ours / steps
    per_mj = t_mj / steps
    print(f"real-time factor, one walker: {SIM_S / ours:.0f}x (target >= 50x)")
    print(f"cost per step ours / MuJoCo native rollout: {per_ours / per_mj:.2f} (target <= 3)")


if __name__ == "__main__":
    main()
