"""Physical and neural simulators behind the motion engines.

``sim.cpg``: the neuro-mechanical biped of seed 001 (CPG + 5-link body + posture controller).
Other simulators (the OBB network, the hexapod) live beside it. Every simulator has the shape
``init(params) -> State``, ``step(params, state, dt, drive) -> State`` and ``rollout(...)``.
"""
